// Lesson 5, section 2: the four kinds of join (see connect.h).
#include "05_bidirectional/connect.h"

#include <cmath>

#include "05_bidirectional/mis.h"

namespace lessons {

namespace {

// s = 0: the camera path's last vertex is on a light (or is the sky): L = beta_C L_e.
Color camera_path_found_light(const Bidir& b, const Vertex& z) {
    if (z.infinite) return z.beta * b.scene.background_radiance(z.p);
    if (z.type != VertexType::Surface) return Color(0.0f);
    return z.beta * b.scene.emitted(z.si);
}

// s = 1: a light sample at z (as next-event estimation takes it), and the light vertex it made.
Color light_sample(const Bidir& b, const Vertex& z, RandomNumbers& rng, Vertex& light) {
    if (!z.connectible() || z.type != VertexType::Surface) return Color(0.0f);
    const float u_choose = rng.uniform();
    const Vec2 u = rng.uniform2();
    const std::optional<LightSample> ls = b.lights.sample(z.si.surface_point(), u_choose, u);
    if (!ls) return Color(0.0f);
    const Color f = z.bsdf->eval(z.si.wo, ls->wi);
    if (is_black(f) || b.scene.occluded(ls->shadow_ray, ls->emitter)) return Color(0.0f);
    light.type = VertexType::Light;
    if (ls->emitter) {
        light.p = ls->point;
        light.n = ls->normal;
        light.emitter = ls->emitter;
        light.pdf_fwd = light_origin_density(b, light);
    } else if (ls->directional) {  // a directional light: its direction
        light.p = ls->wi;
        light.directional = true;
        light.light_index = ls->light_index;
        light.pdf_fwd = ls->pdf;  // its choice probability
    } else if (ls->is_delta) {    // a point light
        light.p = z.p + ls->distance * ls->wi;
        light.point_light = true;
        light.light_index = ls->light_index;
        light.pdf_fwd = ls->pdf;  // its choice probability
    } else {                      // the sky
        light.p = ls->wi;
        light.infinite = true;
        light.pdf_fwd = ls->pdf;
    }
    light.pdf_light_sample = light_sample_density(b, light, z);
    // f L cos / p_light, times the camera side's beta.
    return z.beta * f * ls->radiance * (z.bsdf->abs_cos(ls->wi) / ls->pdf);
}

// t = 1: light vertex y joined to the camera. The importance W = 1 / (A cos^3) already holds
// the camera end's cosine; the light end gives f |cos| / d^2 (for y_0 itself, seen directly:
// the light's emission towards the camera, whose L_e is in y_0's beta; a point light has no
// cosine, and lands as one bright pixel, its power's share).
Color camera_sees(const Bidir& b, const Vertex& y, std::optional<uint32_t>& pixel) {
    if (!y.connectible()) return Color(0.0f);
    const Vec3 to_y = y.p - b.camera.position();
    const float d2 = glm::dot(to_y, to_y);
    if (!(d2 > 0.0f)) return Color(0.0f);
    const Vec3 w = to_y / std::sqrt(d2);  // camera -> y
    const std::optional<Vec2> raster = b.camera.raster_position(w, b.width, b.height);
    if (!raster) return Color(0.0f);
    Color f;
    float cos_y;
    if (y.point_light) {  // a spot's falloff towards the camera (its beta holds the axis's I)
        const PointLight& l = b.scene.point_lights()[y.light_index];
        f = Color(l.cone ? l.cone->falloff(-w) : 1.0f);
        cos_y = 1.0f;
    } else if (y.type == VertexType::Light) {
        cos_y = glm::dot(y.n, -w);
        const bool two_sided = b.scene.material(b.scene.material_of(*y.emitter)).two_sided;
        f = Color(cos_y > 0.0f || two_sided ? 1.0f : 0.0f);
        cos_y = std::fabs(cos_y);
    } else {
        f = light_side_scattering(b, y, -w);  // f |cos|
        cos_y = 1.0f;
    }
    const Color L = y.beta * f * (cos_y / d2 * b.camera.importance(w));
    if (is_black(L) || b.scene.occluded(spawn_ray_to(y.surface_point(), b.camera.position())))
        return Color(0.0f);
    const glm::ivec2 px = pixel_at(b, *raster);
    pixel =
        static_cast<uint32_t>(px.y) * static_cast<uint32_t>(b.width) + static_cast<uint32_t>(px.x);
    return L;
}

}  // namespace

Color join(const Bidir& b, const Vertex& y, const Vertex& z) {
    if (!y.connectible() || !z.connectible() || y.type != VertexType::Surface ||
        z.type != VertexType::Surface)
        return Color(0.0f);
    const Vec3 d = z.p - y.p;
    const float d2 = glm::dot(d, d);
    if (!(d2 > 0.0f)) return Color(0.0f);
    const Vec3 w = d / std::sqrt(d2);  // y -> z
    const Color f_cos_y = light_side_scattering(b, y, w), f_z = z.bsdf->eval(z.si.wo, -w);
    const Color L = y.beta * f_cos_y * (z.bsdf->abs_cos(w) / d2) * f_z * z.beta;
    // z's own surface cannot block the segment (f_z would be 0 from behind it) and must not be
    // asked near t = 1, as next-event estimation's shadow rays ignore the light they end on.
    if (is_black(L) ||
        b.scene.occluded(spawn_ray_between(y.surface_point(), z.surface_point()), z.si.prim))
        return Color(0.0f);
    return L;
}

StrategySample connect(const Bidir& b, std::span<const Vertex> light, int s,
                       std::span<const Vertex> camera, int t, RandomNumbers& rng, bool weighted,
                       const ExtraTechnique* extra) {
    StrategySample out;
    Vertex sampled;  // the vertex the strategy makes itself (s = 1, t = 1), for the weight
    const Vertex *light_end = nullptr, *camera_end = nullptr;
    if (s == 0) {
        out.L = camera_path_found_light(b, camera[t - 1]);
    } else if (t == 1) {
        out.L = camera_sees(b, light[s - 1], out.pixel);
        sampled.type = VertexType::Camera;
        sampled.p = b.camera.position();
        camera_end = &sampled;
    } else if (s == 1) {
        out.L = light_sample(b, camera[t - 1], rng, sampled);
        light_end = &sampled;
    } else {
        out.L = join(b, light[s - 1], camera[t - 1]);
    }
    if (!is_black(out.L) && weighted)
        out.weight = mis_weight(b, light, s, camera, t, light_end, camera_end, extra);
    return out;
}

}  // namespace lessons
