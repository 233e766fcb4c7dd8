// Given paths, for the tests that the weights of every technique that can make one path sum to
// one (lesson 5's joins, Bidirectional.MisWeightsOfEveryStrategySumToOne; lesson 6's joins and
// merges, Vcm.WeightsOfEveryJoinAndMergeSumToOne): a path x_0 (the light) ... x_{n-1} (the
// camera) is made from both ends by subpaths_along (subpaths.h), split at every s, and each
// split the joins can run (connect.h) is weighed as connect() weighs it, with lesson 5's hook
// for an extra technique (mis.h) where a test gives one (test_vcm.cpp adds the merges). The
// scenes hold every kind of light and vertex the weights treat apart, and each comes with its
// paths.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "05_bidirectional/mis.h"
#include "05_bidirectional/subpaths.h"
#include "scene/environment.h"
#include "scene/scene.h"

namespace lessons::test {

struct GivenPath {
    std::string name;
    Vertex light;              // x_0 (see subpaths_along)
    std::vector<Vec3> points;  // x_1 .. x_{n-2}
};

// A point p of the lamp made of material `lamp` (the only primitive with it), its emitting side
// facing n.
inline Vertex on_area_light(const Scene& scene, uint32_t lamp, const Vec3& p, const Vec3& n) {
    Vertex v;
    v.type = VertexType::Light;
    v.p = p;
    v.n = glm::normalize(n);
    for (const AreaLight& light : scene.area_lights())
        if (light.material == lamp) v.emitter = light.prim;
    return v;
}

inline Vertex point_light_at(const Vec3& p) {
    Vertex v;
    v.type = VertexType::Light;
    v.p = p;
    v.point_light = true;
    return v;
}

// A directional light whose light comes from `dir` (towards it).
inline Vertex directional_from(const Vec3& dir) {
    Vertex v;
    v.type = VertexType::Light;
    v.p = glm::normalize(dir);
    v.directional = true;
    return v;
}

inline Vertex sky_towards(const Vec3& dir) {
    Vertex v;
    v.type = VertexType::Light;
    v.p = glm::normalize(dir);
    v.infinite = true;
    return v;
}

inline uint32_t add_material(Scene& scene, MaterialType type, const Color& albedo,
                             const Color& emission = Color(0.0f), bool two_sided = false) {
    Material m;
    m.name = "m" + std::to_string(scene.materials().size());
    m.type = type;
    m.albedo.value = albedo;
    m.reflectance = albedo;
    m.specular = Color(0.5f);
    m.roughness = 0.3f;
    m.emission = emission;
    m.two_sided = two_sided;
    return scene.add_material(m);
}

// Two mirrors facing each other (x = -mirror_x facing +x, x = +mirror_x facing -x): the points
// on them where light from a reaches b, first off the one at +x, then off the one at -x (by
// image sources: b's image in the -x mirror, and that image's in the +x mirror).
inline std::pair<Vec3, Vec3> two_mirror_bounce(const Vec3& a, const Vec3& b, float mirror_x) {
    const Vec3 b2(-2.0f * mirror_x - b.x, b.y, b.z);     // b in the mirror at -x
    const Vec3 b21(2.0f * mirror_x - b2.x, b2.y, b2.z);  // and that in the mirror at +x
    const Vec3 m1 = a + (mirror_x - a.x) / (b21.x - a.x) * (b21 - a);
    const Vec3 m2 = m1 + (-mirror_x - m1.x) / (b2.x - m1.x) * (b2 - m1);
    return {m1, m2};
}

// The weights of one path's techniques: each connection strategy's (s = 0, 1, ...) and, with
// merging, each merge's (at x_1, x_2, ...), in that order.
struct WeightSum {
    double sum = 0.0;
    std::string terms;  // "s=0: 0.31, s=1: 0.69, merge 1: 0.0", for the messages
    int strategies = 0;
    float first = -1.0f;  // the first strategy's weight
    std::vector<float> connections, merges;

    // Adds technique `name`'s weight w.
    void record(const std::string& name, float w) {
        if (strategies == 0) first = w;
        sum += w;
        terms += (terms.empty() ? "" : ", ") + name + ": " + std::to_string(w);
        ++strategies;
    }
};

// The weights of every strategy that can make `path`, each as connect() weighs it (mis_weight,
// with `extra` among the techniques if given).
inline WeightSum weights_of_every_strategy(const Bidir& b, const GivenPath& path,
                                           const ExtraTechnique* extra = nullptr) {
    WeightSum out;
    std::string why;
    const std::optional<GivenSubpaths> sub = subpaths_along(b, path.light, path.points, &why);
    if (!sub) {
        ADD_FAILURE() << path.name << ": " << why;
        return out;
    }
    const int n = static_cast<int>(path.points.size()) + 2;
    const std::vector<Vertex>& camera = sub->camera;  // camera[j] is x_{n-1-j}
    auto delta = [&](int i) { return camera[n - 1 - i].bsdf->is_delta(); };  // 1 <= i <= n-2
    const bool sky = path.light.infinite, point = path.light.delta_light();
    for (int s = 0; s < n; ++s) {
        const int t = n - s;
        // Which joins can run (connect.cpp): not at a mirror or glass; s = 0 only where the
        // camera path can hit x_0 (not a point or directional light); the sky starts no light
        // subpaths; and
        // s >= 1 only where its sampler can choose x_0's light at all.
        bool runs;
        if (s == 0)
            runs = !point;
        else if (sky)
            runs = s == 1 && t >= 2 && !delta(1) && b.lights.environment_pdf(path.light.p) > 0.0f;
        else if (t == 1)
            runs = n == 2 || !delta(n - 2);
        else if (s == 1)
            runs = !delta(1);
        else
            runs = !delta(s - 1) && !delta(s);
        if (s >= 1 && !sky) runs = runs && sub->light[0].pdf_fwd > 0.0f;
        if (!runs) continue;
        Vertex light_sample, camera_end;
        const Vertex* sampled = nullptr;
        const Vertex* end = nullptr;
        if (s == 1 && t >= 2) {  // as connect's light sample makes x_0
            if (sky) {
                light_sample = path.light;
                light_sample.pdf_fwd = b.lights.environment_pdf(light_sample.p);
            } else {
                light_sample = sub->light[0];
                light_sample.pdf_rev = 0.0f;
            }
            light_sample.pdf_light_sample = light_sample_density(b, light_sample, camera[t - 1]);
            sampled = &light_sample;
        }
        if (t == 1) {
            camera_end.type = VertexType::Camera;
            camera_end.p = b.camera.position();
            end = &camera_end;
        }
        const std::span<const Vertex> light_part =
            sampled ? std::span<const Vertex>() : std::span<const Vertex>(sub->light).first(s);
        const float w = mis_weight(b, light_part, s, std::span<const Vertex>(camera).first(t), t,
                                   sampled, end, extra);
        EXPECT_TRUE(w >= 0.0f && w <= 1.0f) << path.name << ", s = " << s << ": " << w;
        out.connections.push_back(w);
        out.record("s=" + std::to_string(s), w);
    }
    return out;
}

// A room with every kind of light and vertex the weights treat apart: a one-sided rectangle on
// the ceiling, a sphere lamp, a two-sided square lamp, a point light, a spot light, a directional
// light (the room has no ceiling); a diffuse floor, a glossy wall, two flat mirrors facing each
// other, a glass ball.
struct Room {
    Scene scene;
    uint32_t ceiling = 0, globe = 0, two_sided = 0;  // the lamps' materials
};

inline Room room_with_every_kind_of_vertex() {
    Room room;
    Scene& scene = room.scene;
    const uint32_t floor = add_material(scene, MaterialType::Diffuse, Color(0.6f));
    const uint32_t wall = add_material(scene, MaterialType::Glossy, Color(0.4f));
    const uint32_t mirror = add_material(scene, MaterialType::Mirror, Color(0.9f));
    const uint32_t glass = add_material(scene, MaterialType::Glass, Color(1.0f));
    scene.add_quad(Quad(Vec3(-3, 0, -4), Vec3(0, 0, 7), Vec3(6, 0, 0)), floor);         // y = 0, up
    scene.add_quad(Quad(Vec3(-3, 0, 2), Vec3(0, 3, 0), Vec3(6, 0, 0)), wall);           // z = 2, -z
    scene.add_quad(Quad(Vec3(2.5f, 0, -2), Vec3(0, 0, 3.5f), Vec3(0, 2, 0)), mirror);   // -x
    scene.add_quad(Quad(Vec3(-2.5f, 0, -2), Vec3(0, 2, 0), Vec3(0, 0, 3.5f)), mirror);  // +x
    scene.add_sphere({Vec3(0.6f, 0.6f, 0.6f), 0.3f}, glass);
    // The lamps: a ceiling rectangle facing down, a sphere, a two-sided square facing -x (and
    // +x).
    room.ceiling = add_material(scene, MaterialType::Diffuse, Color(0.0f), Color(5.0f));
    room.globe = add_material(scene, MaterialType::Diffuse, Color(0.0f), Color(3.0f));
    room.two_sided = add_material(scene, MaterialType::Diffuse, Color(0.0f), Color(2.0f), true);
    scene.add_quad(Quad(Vec3(-0.5f, 2, -0.5f), Vec3(1, 0, 0), Vec3(0, 0, 1)), room.ceiling);
    scene.add_sphere({Vec3(-1.2f, 0.5f, 0.8f), 0.2f}, room.globe);
    scene.add_quad(Quad(Vec3(1.8f, 0.2f, 0), Vec3(0, 0, 0.6f), Vec3(0, 0.6f, 0)), room.two_sided);
    scene.add_point_light({Vec3(-0.5f, 1.5f, 0), Color(2.0f)});
    // A spot above the floor's right half, pointing down and a little forward: 40 degrees to its
    // edge, fading over its outer 30% (in 1 - cos).
    const float cos_outer = std::cos(40.0f * kPi / 180.0f);
    scene.add_point_light({Vec3(1.0f, 1.8f, -0.5f), Color(3.0f),
                           SpotCone{glm::normalize(Vec3(0, -1, 0.3f)), cos_outer,
                                    cos_outer + 0.3f * (1.0f - cos_outer)}});
    scene.add_directional_light({glm::normalize(Vec3(0.6f, -1, -0.3f)), Color(1.5f)});
    scene.width = 24;
    scene.height = 16;
    scene.camera = Camera(Vec3(0, 1.2f, -3), Vec3(0, 0.6f, 0.5f), Vec3(0, 1, 0), 60.0f, 1.5f);
    scene.commit();
    return room;
}

// Paths of every kind of light and vertex in the room, up to six segments.
inline std::vector<GivenPath> paths_in_the_room(const Room& room) {
    const Scene& scene = room.scene;
    const uint32_t ceiling = room.ceiling, globe = room.globe, two_sided = room.two_sided;
    const Vec3 down(0, -1, 0), ball(0.6f, 0.6f, 0.6f);
    const Vec3 sphere_lamp(-1.2f, 0.5f, 0.8f);
    const Vec3 toward_floor = glm::normalize(Vec3(-1.0f, 0, 0.2f) - sphere_lamp);
    const Vec3 before_mirrors(-0.8f, 0, -1.8f), after_mirrors(1.0f, 1.0f, 2);
    const auto [m1, m2] = two_mirror_bounce(before_mirrors, after_mirrors, 2.5f);
    const Vec3 entry = ball + 0.3f * glm::normalize(Vec3(0.1f, 1, 0));
    const Vec3 exit = ball + 0.3f * glm::normalize(Vec3(0.3f, -1, 0));
    const Vec3 under_ball = exit + (-exit.y / -1.0f) * Vec3(0.3f, -1, 0);
    // The point light's image in the mirror at x = -2.5, seen from the floor at (-1.5, 0, -0.5).
    const Vec3 point(-0.5f, 1.5f, 0), image(-4.5f, 1.5f, 0), lit(-1.5f, 0, -0.5f);
    const Vec3 on_mirror = lit + (1.0f / 3.0f) * (image - lit);
    // The spot: a point of the floor in its full cone, one in its fade, and a caustic through the
    // ball (entering on its side towards the spot, leaving underneath).
    const Vec3 spot(1.0f, 1.8f, -0.5f), spot_fade(-0.2f, 0, 0.9f);  // cos 0.825 from the axis
    const Vec3 spot_entry = ball + 0.3f * glm::normalize(spot - ball);
    const Vec3 spot_exit = ball + 0.3f * glm::normalize(Vec3(-0.1f, -1, 0.2f));
    const Vec3 spot_under = spot_exit + spot_exit.y * Vec3(-0.1f, -1, 0.2f);
    // The sun's light travels along `sun`. By way of the mirror at x = 2.5 (at sun_on_mirror) it
    // reaches the floor at sun_lit; through the ball, the floor under it.
    const Vec3 sun = glm::normalize(Vec3(0.6f, -1, -0.3f));
    const Vec3 sun_on_mirror(2.5f, 1.5f, 0), reflected(-0.6f, -1, -0.3f);
    const Vec3 sun_lit = sun_on_mirror + 1.5f * reflected;  // y = 0
    const Vec3 sun_entry = ball - 0.3f * sun;
    const Vec3 sun_exit = ball + 0.3f * glm::normalize(Vec3(0.2f, -1, 0.3f));
    const Vec3 sun_under = sun_exit + sun_exit.y * Vec3(0.2f, -1, 0.3f);
    return {{"rectangle, floor",
             on_area_light(scene, ceiling, Vec3(0.1f, 2, 0.05f), down),
             {Vec3(0.2f, 0, -0.6f)}},
            {"rectangle, floor, glossy wall",
             on_area_light(scene, ceiling, Vec3(-0.2f, 2, 0.1f), down),
             {Vec3(-0.4f, 0, 0.3f), Vec3(0.3f, 0.9f, 2)}},
            {"rectangle seen from near its plane",
             on_area_light(scene, ceiling, Vec3(0.2f, 2, 0.4f), down),
             {Vec3(0.3f, 1.999f, 2)}},
            {"rectangle, floor, wall near the lamp's plane, floor",
             on_area_light(scene, ceiling, Vec3(0.2f, 2, 0.4f), down),
             {Vec3(-0.3f, 0, 0.9f), Vec3(0.3f, 1.998f, 2), Vec3(0.1f, 0, -1.0f)}},
            {"sphere lamp, floor",
             on_area_light(scene, globe, sphere_lamp + 0.2f * toward_floor, toward_floor),
             {Vec3(-1.0f, 0, 0.2f)}},
            {"sphere lamp, floor, glossy wall",
             on_area_light(scene, globe, sphere_lamp + 0.2f * toward_floor, toward_floor),
             {Vec3(-1.0f, 0, 0.2f), Vec3(-0.6f, 1.1f, 2)}},
            {"two-sided lamp, from its back",
             on_area_light(scene, two_sided, Vec3(1.8f, 0.5f, 0.3f), Vec3(1, 0, 0)),
             {Vec3(2.2f, 0, 0.0f)}},
            {"two-sided lamp, from its front, floor, wall",
             on_area_light(scene, two_sided, Vec3(1.8f, 0.5f, 0.3f), Vec3(-1, 0, 0)),
             {Vec3(1.2f, 0, 0.4f), Vec3(0.9f, 1.0f, 2)}},
            {"rectangle, floor, two flat mirrors, glossy wall",
             on_area_light(scene, ceiling, Vec3(-0.3f, 2, -0.3f), down),
             {before_mirrors, m1, m2, after_mirrors}},
            {"rectangle, glass ball, floor (a caustic)",
             on_area_light(scene, ceiling, Vec3(0.45f, 2, 0.45f), down),
             {entry, exit, under_ball}},
            {"point light, floor", point_light_at(point), {Vec3(-0.3f, 0, -0.9f)}},
            {"point light, floor, glossy wall",
             point_light_at(point),
             {Vec3(-0.3f, 0, 0.2f), Vec3(-0.2f, 0.7f, 2)}},
            {"point light, mirror, floor (only light tracing)",
             point_light_at(point),
             {on_mirror, lit}},
            {"point light seen directly", point_light_at(point), {}},
            {"spot light, floor in its full cone", point_light_at(spot), {Vec3(1.0f, 0, 0.0f)}},
            {"spot light, floor in its fade, glossy wall",
             point_light_at(spot),
             {spot_fade, Vec3(0.4f, 1.0f, 2)}},
            {"spot light, glass ball, floor (a caustic)",
             point_light_at(spot),
             {spot_entry, spot_exit, spot_under}},
            {"sun, floor", directional_from(-sun), {Vec3(-0.6f, 0, -1.2f)}},
            {"sun, floor, glossy wall",
             directional_from(-sun),
             {Vec3(-0.6f, 0, 0.4f), Vec3(0.2f, 0.8f, 2)}},
            {"sun, mirror, floor (only light tracing)",
             directional_from(-sun),
             {sun_on_mirror, sun_lit}},
            {"sun, glass ball, floor (a caustic)",
             directional_from(-sun),
             {sun_entry, sun_exit, sun_under}},
            {"sun, floor, two flat mirrors, glossy wall",
             directional_from(-sun),
             {before_mirrors, m1, m2, after_mirrors}}};
}

// An open scene under the sky: uniform, or a map with a sun 1e9 times its other texels, turned
// by 30 degrees; a diffuse ground, a metal plate, a mirror.
inline Scene open_sky(bool map) {
    Scene open;
    const uint32_t ground = add_material(open, MaterialType::Diffuse, Color(0.5f));
    const uint32_t plate = add_material(open, MaterialType::Conductor, Color(0.5f));
    open.add_quad(Quad(Vec3(-3, 0, -4), Vec3(0, 0, 7), Vec3(6, 0, 0)), ground);
    open.add_quad(Quad(Vec3(-3, 0, 2), Vec3(0, 1, 0), Vec3(6, 0, 0)), plate);
    open.add_quad(Quad(Vec3(-2.5f, 0, -2), Vec3(0, 1, 0), Vec3(0, 0, 3.5f)),
                  add_material(open, MaterialType::Mirror, Color(0.9f)));
    if (map) {  // the sun in the top row: every other row comes after it in the table
        std::vector<Color> texels(16 * 8, Color(1e-9f));
        texels[5] = Color(1.0f);
        open.environment_map = std::make_shared<const EnvironmentMap>(16, 8, texels, 30.0f, 1.0f);
    } else {
        open.background = Color(0.5f);
    }
    open.width = 24;
    open.height = 16;
    open.camera = Camera(Vec3(0, 1.2f, -3), Vec3(0, 0.6f, 0.5f), Vec3(0, 1, 0), 60.0f, 1.5f);
    open.commit();
    return open;
}

inline std::vector<GivenPath> paths_under_the_sky() {
    const Vec3 up_left = glm::normalize(Vec3(-1.0f, 0.4f, 0.3f));
    const Vec3 lit_floor(-1.5f, 0, -0.5f);
    const Vec3 seen_in_mirror = glm::normalize(Vec3(2.0f, 1.0f, 0.1f));  // from the mirror
    const Vec3 on_plane = lit_floor + 0.5f * Vec3(-2.0f, 1.0f, 0.1f);    // x = -2.5
    return {{"sky, ground", sky_towards(up_left), {Vec3(0.2f, 0, -0.6f)}},
            {"sky, ground, metal plate",
             sky_towards(up_left),
             {Vec3(0.1f, 0, 0.4f), Vec3(0.3f, 0.6f, 2)}},
            {"sky, mirror, ground", sky_towards(seen_in_mirror), {on_plane, lit_floor}},
            {"sky seen directly", sky_towards(Vec3(0.1f, 0.8f, 3)), {}}};
}

// A lamp after one 1e9 times brighter in the table the lights are chosen from (point lights
// come first): its share of the power, about 1e-10, is below a float's resolution near 1. The
// camera is the room's. `faint` is the lamp's material.
struct FaintLamp {
    Scene scene;
    uint32_t faint = 0;
};

inline FaintLamp faint_lamp_after_a_bright_light() {
    FaintLamp out;
    Scene& pair = out.scene;
    pair.add_quad(Quad(Vec3(-3, 0, -4), Vec3(0, 0, 7), Vec3(6, 0, 0)),
                  add_material(pair, MaterialType::Diffuse, Color(0.5f)));
    pair.add_quad(Quad(Vec3(-3, 0, 2), Vec3(0, 3, 0), Vec3(6, 0, 0)),
                  add_material(pair, MaterialType::Diffuse, Color(0.5f)));
    out.faint = add_material(pair, MaterialType::Diffuse, Color(0.0f), Color(1.0f));
    pair.add_quad(Quad(Vec3(-0.5f, 2, -0.5f), Vec3(1, 0, 0), Vec3(0, 0, 1)), out.faint);
    pair.add_point_light({Vec3(2, 1, 1), Color(1e9f)});
    pair.width = 24;
    pair.height = 16;
    pair.camera = Camera(Vec3(0, 1.2f, -3), Vec3(0, 0.6f, 0.5f), Vec3(0, 1, 0), 60.0f, 1.5f);
    pair.commit();
    return out;
}

inline std::vector<GivenPath> paths_of_the_faint_lamp(const FaintLamp& pair) {
    const Vec3 down(0, -1, 0);
    return {{"a faint lamp, floor",
             on_area_light(pair.scene, pair.faint, Vec3(0.1f, 2, 0.05f), down),
             {Vec3(0.2f, 0, -0.6f)}},
            {"a faint lamp, floor, wall",
             on_area_light(pair.scene, pair.faint, Vec3(0.1f, 2, 0.05f), down),
             {Vec3(0.2f, 0, -0.6f), Vec3(-0.4f, 1.2f, 2)}}};
}

}  // namespace lessons::test
