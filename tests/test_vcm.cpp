// Lesson 6's vertex connection and merging (docs/accuracy.md, "Density estimation"): the weights
// of every join and merge of a path sum to one; without merging it is lesson 5 bit for bit; and
// it finds the light of paths no unbiased estimator here can make.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "05_bidirectional/bidirectional.h"
#include "05_bidirectional/mis.h"
#include "06_photon_mapping/merge_weights.h"
#include "06_photon_mapping/photon_mapping.h"
#include "06_photon_mapping/radius.h"
#include "given_paths.h"
#include "image_sources.h"
#include "io/scene_file.h"
#include "render_statistics.h"
#include "test_util.h"

using namespace lessons;
using test::point_irradiance;

namespace {

// Paths that only merging can make, or that merging shares with a camera ray hitting the lamp:
// light onto the floor through a mirror or a glass ball, seen from the floor through a mirror
// or the ball again (L S D S E), in the room of test::room_with_every_kind_of_vertex.
std::vector<test::GivenPath> caustics_seen_through_delta_vertices(const test::Room& room) {
    const Vec3 ball(0.6f, 0.6f, 0.6f), point(-0.5f, 1.5f, 0);
    // The floor point f sees the point light in the mirror at x = -2.5 (its image at x = -4.5)
    // and is seen by the camera in the mirror at x = +2.5 (the camera's image at x = 5).
    const Vec3 f(1.5f, 0, 1.9f), camera_image(5.0f, 1.2f, -3.0f);
    const Vec3 on_left = f + ((-2.5f - f.x) / (-4.5f - f.x)) * (Vec3(-4.5f, 1.5f, 0) - f);
    const Vec3 on_right = f + ((2.5f - f.x) / (camera_image.x - f.x)) * (camera_image - f);
    // The ceiling lamp's point p, seen from f in the mirror at x = -2.5 (its image at x = -4.7).
    const Vec3 p(-0.3f, 2, 0.2f);
    const Vec3 lamp_on_left = f + ((-2.5f - f.x) / (-4.7f - f.x)) * (Vec3(-4.7f, 2, 0.2f) - f);
    // Through the ball: light enters at the top (or the side facing the point light) and leaves
    // at the bottom onto the floor; the camera sees that floor point through the ball (entering
    // at its front, leaving at its bottom). A delta vertex's direction need not obey Snell's
    // law here: the weights read the densities of the given vertices only.
    const Vec3 entry = ball + 0.3f * glm::normalize(Vec3(0.1f, 1, 0));
    const Vec3 from_point = ball + 0.3f * glm::normalize(point - ball);
    const Vec3 exit = ball + 0.3f * glm::normalize(Vec3(0.3f, -1, 0));
    const Vec3 under_ball = exit + (-exit.y / -1.0f) * Vec3(0.3f, -1, 0);
    const Vec3 back_in = ball + 0.3f * glm::normalize(Vec3(-0.2f, -1, -0.3f));
    const Vec3 front = ball + 0.3f * glm::normalize(Vec3(-0.1f, 0, -1));
    const Vec3 down(0, -1, 0);
    return {{"point light, mirror, floor, mirror (merging alone)",
             test::point_light_at(point),
             {on_left, f, on_right}},
            {"point light, glass ball, floor, glass ball (merging alone)",
             test::point_light_at(point),
             {from_point, exit, under_ball, back_in, front}},
            {"rectangle, mirror, floor, mirror",
             test::on_area_light(room.scene, room.ceiling, p, down),
             {lamp_on_left, f, on_right}},
            {"rectangle, glass ball, floor, glass ball (the caustic seen through glass)",
             test::on_area_light(room.scene, room.ceiling, Vec3(0.45f, 2, 0.45f), down),
             {entry, exit, under_ball, back_in, front}}};
}

// The weights of every technique that can make `path` at eta = N pi r^2: every join, as
// connect() weighs it with the merges as lesson 5's extra technique (MergeTechnique), and every
// merge, as merges() weighs it (merge_weight, merge_weights.h): at each vertex x_j,
// 1 <= j <= n - 2, whose BSDF is not a delta, the light subpath x_0 .. x_{j-1} and its vertex at
// x_j (the photon) merged with the camera subpath x_{n-1} .. x_j (t = n - j). The sky starts no
// light subpaths, so it makes no photons; nor does a light the sampler never chooses. At eta = 0
// no merge counts, and no merge is made.
test::WeightSum weights_of_every_join_and_merge(const Bidir& b, const test::GivenPath& path,
                                                double eta) {
    const MergeTechnique merge_technique(eta);
    test::WeightSum out = test::weights_of_every_strategy(b, path, &merge_technique);
    const std::optional<GivenSubpaths> sub = subpaths_along(b, path.light, path.points);
    if (!sub || !(eta > 0.0) || path.light.infinite || !(sub->light[0].pdf_fwd > 0.0f)) return out;
    const int n = static_cast<int>(path.points.size()) + 2;
    const std::span<const Vertex> light(sub->light), camera(sub->camera);  // camera[i]: x_{n-1-i}
    for (int j = 1; j <= n - 2; ++j) {
        const int t = n - j;
        if (camera[t - 1].bsdf->is_delta()) continue;  // no photon is left there
        const float w = merge_weight(b, light.first(j), j, light[j], camera.first(t), t, eta);
        EXPECT_TRUE(w >= 0.0f && w <= 1.0f) << path.name << ", merge at " << j << ": " << w;
        out.merges.push_back(w);
        out.record("merge " + std::to_string(j), w);
    }
    return out;
}

// The weights of every path in `paths` in lesson 5 (no merges; at eta = 0 the same, bit for bit)
// and at the given etas: the joins' and merges' weights sum to 1; adding merges only takes weight
// from the joins; as eta goes to 0 the joins' weights become lesson 5's and the merges' vanish.
// Returns the merges' largest weight at each eta (to see that merging took a share).
std::vector<float> expect_joins_and_merges_sum_to_one(const Bidir& b,
                                                      const std::vector<test::GivenPath>& paths,
                                                      const std::vector<double>& etas) {
    std::vector<float> largest(etas.size(), 0.0f);
    for (const test::GivenPath& path : paths) {
        const test::WeightSum lesson5 = test::weights_of_every_strategy(b, path);
        const test::WeightSum at_zero = weights_of_every_join_and_merge(b, path, 0.0);
        EXPECT_TRUE(at_zero.merges.empty()) << path.name;
        EXPECT_EQ(at_zero.connections, lesson5.connections) << path.name;
        if (!lesson5.connections.empty()) {
            EXPECT_NEAR(lesson5.sum, 1.0, 1e-5) << path.name << " (" << lesson5.terms << ")";
        }
        for (size_t e = 0; e < etas.size(); ++e) {
            const test::WeightSum w = weights_of_every_join_and_merge(b, path, etas[e]);
            EXPECT_GE(w.strategies, 1) << path.name;
            EXPECT_NEAR(w.sum, 1.0, 1e-5)
                << path.name << ", eta " << etas[e] << " (" << w.terms << ")";
            EXPECT_EQ(w.connections.size(), lesson5.connections.size()) << path.name;
            if (w.connections.size() != lesson5.connections.size()) continue;
            for (size_t k = 0; k < w.connections.size(); ++k)
                EXPECT_LE(w.connections[k], lesson5.connections[k] + 1e-6f)
                    << path.name << ", eta " << etas[e] << ": join " << k << " gained weight";
            for (const float m : w.merges) largest[e] = std::max(largest[e], m);
        }
        // eta -> 0: lesson 5's joins, merges of no weight.
        const test::WeightSum faint = weights_of_every_join_and_merge(b, path, 1e-9 * etas[0]);
        for (size_t k = 0; k < faint.connections.size(); ++k)
            EXPECT_NEAR(faint.connections[k], lesson5.connections[k], 1e-5) << path.name;
        for (const float m : faint.merges) {
            if (!lesson5.connections.empty()) {
                EXPECT_LT(m, 1e-5f) << path.name;
            }
        }
    }
    return largest;
}

// eta = N pi r^2 for the scene's own N (one light subpath per pixel) and default radius, times
// 1e-3, 1 and 1e3: from merges that hardly count to merges that take almost everything.
std::vector<double> etas_about_the_default(const Scene& scene) {
    const double r = default_photon_radius(scene);
    const double eta = static_cast<double>(scene.width) * scene.height * kPi * r * r;
    return {1e-3 * eta, eta, 1e3 * eta};
}

}  // namespace

TEST(Vcm, WeightsOfEveryJoinAndMergeSumToOne) {
    // Vertex connection and merging weighs every join (s, t) of a path and every merge at one of
    // its vertices x_j (1 <= j <= n - 2, not a mirror or glass) by the power heuristic over all
    // of them, a merge's density being strategy j's times p_L(x_j) eta, eta = N pi r^2
    // (merge_weights.h; Georgiev et al. 2012): for the estimator to be unbiased (as r -> 0) the
    // weights of one path must sum to 1. On lesson 5's given paths
    // (weights_of_every_join_and_merge: each join as connect() weighs it, each merge as merges()
    // does, with the light subpath's vertex at x_j as the photon) in the room with every kind of
    // light and vertex, under a uniform sky and a map with a sun (which leave no photons), and for
    // a lamp 1e10 times fainter than the other light; and on paths that only merging can make (a
    // point light's caustic through a mirror or a glass ball, seen through a mirror or the ball:
    // L S D S E), or that merging shares with a camera ray that hits the lamp. At eta = 0 the
    // joins alone sum to 1, as in lesson 5. A density wrong the same way in every technique would
    // still sum to 1: on the lamp's L S D S E paths the merge's weight is also checked in closed
    // form (merging's density is eta times the photon's density at the merge vertex,
    // docs/06_photon_mapping.md).
    const test::Room room = test::room_with_every_kind_of_vertex();
    const LightSampler lights(room.scene);
    const Bidir b{room.scene, lights, room.scene.camera, room.scene.width, room.scene.height};
    const std::vector<double> etas = etas_about_the_default(room.scene);
    const std::vector<float> largest =
        expect_joins_and_merges_sum_to_one(b, test::paths_in_the_room(room), etas);
    EXPECT_LT(largest[0], 0.5f) << "at 1e-3 eta the merges should take little";
    EXPECT_GT(largest[2], 0.5f) << "at 1e3 eta the merges should take most";

    const std::vector<test::GivenPath> caustics = caustics_seen_through_delta_vertices(room);
    // The lights are chosen by power (lights.h): the ceiling's pi A L_e = 5 pi, the sphere's
    // pi (4 pi 0.2^2) 3, the two-sided square's 2 pi 0.6^2 2, the point light's 4 pi 2, the
    // spot's 3 times its cone's solid angle, the sun's E pi R^2 (R: the room's bounding sphere).
    const double cos_outer = std::cos(40.0 * kPi / 180.0);
    const double cos_inner = cos_outer + 0.3 * (1.0 - cos_outer);
    const double spot = 3.0 * 2.0 * kPi * ((1.0 - cos_inner) + 0.5 * (cos_inner - cos_outer));
    const double sun = 1.5 * kPi * lights.beam_radius() * lights.beam_radius();
    const double ceiling_choice = 5.0 * kPi /
                                  (5.0 * kPi + kPi * 4.0 * kPi * 0.04 * 3.0 +
                                   2.0 * kPi * 0.36 * 2.0 + 4.0 * kPi * 2.0 + spot + sun);
    expect_joins_and_merges_sum_to_one(b, caustics, etas);
    for (const double eta : etas) {
        for (int k = 0; k < 2; ++k) {  // the point light's: the merge at the floor alone
            const test::WeightSum w = weights_of_every_join_and_merge(b, caustics[k], eta);
            EXPECT_TRUE(w.connections.empty()) << caustics[k].name << " (" << w.terms << ")";
            ASSERT_EQ(w.merges.size(), 1u) << caustics[k].name;
            EXPECT_NEAR(w.merges[0], 1.0f, 1e-6f) << caustics[k].name;
        }
        for (int k = 2; k < 4; ++k) {  // the lamp's: a camera ray hitting it, and the merge
            const test::WeightSum w = weights_of_every_join_and_merge(b, caustics[k], eta);
            ASSERT_EQ(w.connections.size(), 1u) << caustics[k].name << " (" << w.terms << ")";
            ASSERT_EQ(w.merges.size(), 1u) << caustics[k].name << " (" << w.terms << ")";
            // Both make x_0 and the diffuse x_j with cosine densities (the lamp's emission, the
            // floor's BSDF) across the same unfolded chain, so p_merge / p_0 = p_L(x_0) eta,
            // p_L(x_0) the lamp's choice probability over its area: w = x^2 / (1 + x^2).
            const double x = eta * ceiling_choice / 1.0;  // the ceiling lamp is 1 m^2
            EXPECT_NEAR(w.merges[0], x * x / (1.0 + x * x), 1e-5) << caustics[k].name;
        }
    }

    for (const bool map : {false, true}) {
        const Scene open = test::open_sky(map);
        const LightSampler sky_lights(open);
        const Bidir sb{open, sky_lights, open.camera, open.width, open.height};
        expect_joins_and_merges_sum_to_one(sb, test::paths_under_the_sky(),
                                           etas_about_the_default(open));
        for (const test::GivenPath& path : test::paths_under_the_sky())
            EXPECT_TRUE(weights_of_every_join_and_merge(sb, path, 1.0).merges.empty());
    }

    const test::FaintLamp pair = test::faint_lamp_after_a_bright_light();
    const LightSampler pair_lights(pair.scene);
    const Bidir pb{pair.scene, pair_lights, pair.scene.camera, pair.scene.width, pair.scene.height};
    expect_joins_and_merges_sum_to_one(pb, test::paths_of_the_faint_lamp(pair),
                                       etas_about_the_default(pair.scene));
}

TEST(Vcm, AWeighedPhotonGivesItsMergeTheWeightThatSumsToOneWithTheJoins) {
    // merges() does not walk a merge's whole path: it reads the light side of the weight from
    // the photon (weigh_photons stores it as two floats, the roots of its terms), the camera
    // side from its vertex (computed once per vertex), and the two densities of scattering at
    // the merge from the photon's arrival direction (merge_weights.h, "the same weight in two
    // halves"). On every merge of lesson 5's given paths in the room and of the caustics seen
    // through a mirror or a glass ball, at etas from 1e-3 to 1e3 of the default, that gives
    // merge_weight's value: the one Vcm.WeightsOfEveryJoinAndMergeSumToOne checks against every
    // join's.
    const test::Room room = test::room_with_every_kind_of_vertex();
    const LightSampler lights(room.scene);
    const Bidir b{room.scene, lights, room.scene.camera, room.scene.width, room.scene.height};
    std::vector<test::GivenPath> paths = test::paths_in_the_room(room);
    for (const test::GivenPath& path : caustics_seen_through_delta_vertices(room))
        paths.push_back(path);
    int merges = 0;
    for (const double eta : etas_about_the_default(room.scene)) {
        for (const test::GivenPath& path : paths) {
            const std::optional<GivenSubpaths> sub = subpaths_along(b, path.light, path.points);
            ASSERT_TRUE(sub) << path.name;
            if (path.light.infinite || !(sub->light[0].pdf_fwd > 0.0f)) continue;
            const int n = static_cast<int>(path.points.size()) + 2;
            for (int j = 1; j <= n - 2; ++j) {
                const int t = n - j;
                const std::span<const Vertex> camera =
                    std::span<const Vertex>(sub->camera).first(t);
                if (camera[t - 1].bsdf->is_delta()) continue;  // no photon is left there
                const std::span<const Vertex> light = std::span<const Vertex>(sub->light).first(j);
                const Vertex& landed = sub->light[j];
                const float expected = merge_weight(b, light, j, landed, camera, t, eta);
                Photon photon;
                photon.p = landed.p;
                photon.wi = landed.si.wo;
                photon.n = landed.si.n_geo;
                store_light_side(photon, merge_light_side(b, light, landed, eta));
                const float got =
                    merge_weight(photon, merge_camera_side(camera, t, eta), *camera[t - 1].bsdf);
                EXPECT_NEAR(got, expected, 1e-5f + 1e-5f * expected)
                    << path.name << ", merge at " << j << ", eta " << eta;
                ++merges;
            }
        }
    }
    EXPECT_GT(merges, 30);
}

TEST(Vcm, WithoutMergingIsLessonFiveBitForBit) {
    // --method bpt is vertex connection and merging without the merges: lesson 5's strategies,
    // weighted by lesson 5's weights (no extra technique), its light subpaths from the same
    // random numbers, its light tracing splatted in the same order. The image and its variance, bit
    // for bit, against lesson 5's model on the same seed: on the box with a mirror and a glass ball
    // (chains of delta vertices) and Veach's glossy plates and spherical lamps, with a path
    // length limit and Russian roulette.
    for (const char* file : {"/scenes/cornell_spheres.toml", "/scenes/veach_mis.toml"}) {
        const Scene scene = load_scene(std::string(LESSONS_SOURCE_DIR) + file, {24, 16});
        PhotonOptions options;
        options.method = PhotonMethod::Bidirectional;
        options.paths.max_depth = 6;
        options.paths.roulette_after = 2;
        const RenderResult six =
            render_scene(scene, PhotonMappingModel(scene, options), 8, test::quiet_settings(91));
        const RenderResult five = render_scene(scene, BidirectionalModel(scene, options.paths), 8,
                                               test::quiet_settings(91));
        EXPECT_TRUE(test::same_bits(six.image, five.image)) << file;
        EXPECT_TRUE(test::same_bits(six.variance, five.variance)) << file;
        EXPECT_GT(test::image_mean(five.image, five.variance).first, 0.0) << file;
    }
}

TEST(Vcm, MergesOnlyWhereTheSceneHasADeltaSurface) {
    // --merging auto (the default): in the Cornell box (nothing but diffuse walls and a lamp)
    // every path has a join, so vcm leaves merging out and is lesson 5 bit for bit, and says
    // so; --merging always merges there anyway and differs. In the box with a mirror and a
    // glass ball auto merges: the same image bit for bit as always; never is lesson 5 there.
    const RenderSettings settings = test::quiet_settings(92);
    const auto render_vcm = [&](const Scene& scene, Merging merging) {
        PhotonOptions options;
        options.merging = merging;
        const PhotonMappingModel model(scene, options);
        return std::make_pair(render_scene(scene, model, 4, settings), model.notes);
    };
    const Scene box =
        load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/cornell_box.toml", {24, 16});
    EXPECT_FALSE(merges_in(box, Merging::Auto));
    const RenderResult five = render_scene(box, BidirectionalModel(box, {}), 4, settings);
    const auto [auto_box, auto_notes] = render_vcm(box, Merging::Auto);
    EXPECT_TRUE(test::same_bits(auto_box.image, five.image));
    EXPECT_TRUE(test::same_bits(auto_box.variance, five.variance));
    ASSERT_FALSE(auto_notes.empty());
    EXPECT_NE(auto_notes[0].find("merging left out"), std::string::npos) << auto_notes[0];
    EXPECT_FALSE(test::same_bits(render_vcm(box, Merging::Always).first.image, five.image));

    const Scene spheres =
        load_scene(std::string(LESSONS_SOURCE_DIR) + "/scenes/cornell_spheres.toml", {24, 16});
    EXPECT_TRUE(merges_in(spheres, Merging::Auto));
    const RenderResult always = render_vcm(spheres, Merging::Always).first;
    EXPECT_TRUE(test::same_bits(render_vcm(spheres, Merging::Auto).first.image, always.image));
    const RenderResult spheres_five =
        render_scene(spheres, BidirectionalModel(spheres, {}), 4, settings);
    EXPECT_TRUE(
        test::same_bits(render_vcm(spheres, Merging::Never).first.image, spheres_five.image));
    EXPECT_FALSE(test::same_bits(always.image, spheres_five.image));
}

namespace {

// A path no unbiased sampler here can make (docs/06_photon_mapping.md, "What each method
// misses"): a point light (at `light`, just below
// the plane of the receiver, so it lights the receiver's top only through the mirror above), a
// horizontal mirror (reflectance R1, at height H, facing down) that throws the light's image onto
// a diffuse receiver (albedo rho, the square |x|, |z| <= 0.5 at y = 0, facing up), and a camera
// that sees the receiver only in a second, vertical mirror (reflectance R2, the plane z = -1,
// facing +z): every path from the light to the camera through the receiver is L S D S E.
struct CausticInAMirror {
    double I = 1.0, R1 = 0.9, R2 = 0.8, rho = 0.6, H = 0.5;
    Vec3 light{0.8f, -0.05f, 0.0f};
    double half = 0.5;  // the receiver's half side
    // The image source's height over the receiver, and the receiver's irradiance at (x, z).
    double image_height() const { return 2.0 * H - light.y; }
    double irradiance(double x, double z) const {
        return point_irradiance(R1 * I, image_height(), std::hypot(x - light.x, z - light.z));
    }
};

Scene caustic_seen_only_in_a_mirror(const CausticInAMirror& c) {
    Scene scene;
    const uint32_t receiver =
        test::add_material(scene, MaterialType::Diffuse, Color(static_cast<float>(c.rho)));
    const uint32_t over =
        test::add_material(scene, MaterialType::Mirror, Color(static_cast<float>(c.R1)));
    const uint32_t beside =
        test::add_material(scene, MaterialType::Mirror, Color(static_cast<float>(c.R2)));
    const float s = static_cast<float>(c.half), H = static_cast<float>(c.H);
    scene.add_quad(Quad(Vec3(-s, 0, -s), Vec3(0, 0, 2 * s), Vec3(2 * s, 0, 0)), receiver);  // +y
    scene.add_quad(Quad(Vec3(-2, H, -2), Vec3(4, 0, 0), Vec3(0, 0, 4)), over);              // -y
    scene.add_quad(Quad(Vec3(-2, -0.3f, -1), Vec3(4, 0, 0), Vec3(0, 0.75f, 0)), beside);    // +z
    scene.add_point_light({c.light, Color(static_cast<float>(c.I))});
    // Above the receiver, looking at its image in the vertical mirror (at z = -2): the camera's
    // rays go down between 7 and 21 degrees, the receiver itself lies more than 50 degrees down.
    scene.width = 48;
    scene.height = 32;
    scene.camera = Camera(Vec3(0, 0.4f, -0.2f), Vec3(0, 0, -2), Vec3(0, 1, 0), 14.0f, 1.5f);
    scene.commit();
    return scene;
}

// The receiver point (x, z) that the ray sees in the vertical mirror, if it does.
std::optional<std::pair<double, double>> seen_in_the_mirror(const Ray& ray) {
    const double t = (-1.0 - ray.origin.z) / ray.dir.z;
    if (!(t > 0.0)) return std::nullopt;
    const double mx = ray.origin.x + t * ray.dir.x, my = ray.origin.y + t * ray.dir.y;
    if (my < -0.3 || my > 0.45 || std::fabs(mx) > 2.0 || !(ray.dir.y < 0.0f)) return std::nullopt;
    const double u = -my / ray.dir.y;  // on along (dx, dy, -dz) to y = 0
    return std::make_pair(mx + u * ray.dir.x, -1.0 - u * ray.dir.z);
}

}  // namespace

TEST(Vcm, APointLightsCausticSeenOnlyInAMirrorIsFound) {
    // The receiver's light comes from the point light's image in the mirror above it, and the
    // camera sees it only in the mirror beside it: the pixels that see the receiver carry
    // R2 (rho / pi) E(x), E(x) = R1 I h' / (h'^2 + d^2)^(3/2) (h' the image's height, d the
    // distance from its foot), and nothing else reaches the camera (within 4 segments; the
    // receiver's own light reflected back by the mirror above takes 5). No join can make these
    // paths (each would end at a mirror or at the point light), so lesson 5 (bpt) shows nothing
    // there; only merging can, and at the receiver its weight is 1 (Vcm.WeightsOfEvery...), so
    // vcm's expectation at a pixel is the kernel's average of E over the disk about x (kernel.h)
    // at each pass's radius, r_k = r_1 k^(-1/8), averaged over the passes; tested at the pixels
    // whose disk lies on the receiver at every pass (their centres, no jitter). Per pixel, a
    // z-test with the film's variance (independent passes), Sidak-corrected over the pixels;
    // then the mean over those pixels, with its standard error from the passes' means (the
    // pixels share photons, so their errors are correlated).
    const CausticInAMirror c;
    const Scene scene = caustic_seen_only_in_a_mirror(c);
    PhotonOptions options;
    options.method = PhotonMethod::VertexMerging;
    options.radius = 0.1f;
    options.paths.max_depth = 4;
    const PhotonMappingModel vcm(scene, options);
    const int passes = 1024;
    RenderSettings settings = test::quiet_settings(92);
    settings.jitter = false;

    struct Tested {
        size_t pixel;
        double x, z;
    };
    std::vector<Tested> tested;
    const double inside = c.half - options.radius;
    test::for_each_pixel_center(
        scene.camera, scene.width, scene.height, [&](int px, int py, Ray ray) {
            const auto seen = seen_in_the_mirror(ray);
            if (!seen || std::fabs(seen->first) > inside || std::fabs(seen->second) > inside)
                return;
            tested.push_back(
                {static_cast<size_t>(py) * scene.width + px, seen->first, seen->second});
        });
    ASSERT_GE(tested.size(), 200u);
    std::vector<double> expected(tested.size(), 0.0), unblurred(tested.size());
    for (size_t i = 0; i < tested.size(); ++i) {
        const double f = c.R2 * c.rho / kPi;
        unblurred[i] = f * c.irradiance(tested[i].x, tested[i].z);
        for (int k = 1; k <= passes; ++k) {
            const double r = options.radius * std::pow(k, (vcm.alpha() - 1.0) / 2.0);
            expected[i] +=
                f / passes *
                test::kernel_average(Kernel::Constant, r, tested[i].x, tested[i].z,
                                     [&](double x, double z) { return c.irradiance(x, z); });
        }
    }

    // Pass by pass, for the passes' means over the tested pixels.
    ProgressiveFilms films(scene, vcm, 0.0f);
    std::vector<double> pass_means;
    double before = 0.0;
    for (int k = 1; k <= passes; ++k) {
        ASSERT_TRUE(films.render_to(k, settings));
        double sum = 0.0;
        for (const Tested& t : tested) sum += films.films()[0].pixels()[t.pixel].total().x;
        pass_means.push_back((sum - before) / tested.size());
        before = sum;
    }
    const RenderResult r = films.result();
    const double z_pixel = test::z_quantile(test::sidak(0.01, static_cast<int>(tested.size())));
    double mean_expected = 0.0, mean_unblurred = 0.0;
    int failed = 0;
    for (size_t i = 0; i < tested.size(); ++i) {
        const double v = r.image.pixels[tested[i].pixel].x;
        const double var = r.variance.pixels[tested[i].pixel].x;
        const double z = std::fabs(v - expected[i]) / std::sqrt(std::max(var, 1e-14));
        if (z >= z_pixel && ++failed <= 5)
            ADD_FAILURE() << "pixel " << tested[i].pixel << " (receiver " << tested[i].x << ", "
                          << tested[i].z << "): " << v << " against " << expected[i]
                          << " (standard error " << std::sqrt(var) << ")";
        mean_expected += expected[i] / tested.size();
        mean_unblurred += unblurred[i] / tested.size();
    }
    EXPECT_EQ(failed, 0) << "of " << tested.size() << " pixels";
    const test::MeanAndError m = test::mean_and_error(pass_means);
    const double z_mean = std::fabs(m.mean - mean_expected) / m.standard_error;
    std::printf(
        "vcm: %zu pixels see the receiver; mean %.6f (standard error %.6f), expected %.6f "
        "(unblurred %.6f): z %.2f\n",
        tested.size(), m.mean, m.standard_error, mean_expected, mean_unblurred, z_mean);
    EXPECT_LT(z_mean, test::z_quantile(0.01));

    // Lesson 5 on the same scene: nothing on those pixels (no pass of it could find any).
    PhotonOptions bpt = options;
    bpt.method = PhotonMethod::Bidirectional;
    const RenderResult five = render_scene(scene, PhotonMappingModel(scene, bpt), 64, settings);
    double five_mean = 0.0;
    for (const Tested& t : tested) five_mean += five.image.pixels[t.pixel].x / tested.size();
    std::printf("bpt: mean %.6g on the same pixels\n", five_mean);
    EXPECT_LT(five_mean, 1e-3 * mean_expected);
}
