// Lesson 6: photons. Lesson 5 joins a camera subpath to a light subpath by a segment; where the
// path has a diffuse vertex between two mirror or glass vertices (light from a small lamp,
// through glass, onto a floor, then through glass again to the eye: L S+ D S+ E), no segment can
// be joined (either end of it sits at a delta BSDF), and lesson 5 finds such paths only when a
// camera path happens to hit the lamp. Density estimation finds them: light subpaths leave
// photons on the surfaces (photons.h), and a camera path that reaches a diffuse point x takes
// the photons near x as light arriving there (the radiance estimate, density.h):
//
//   L_r(x, wo) ~ (1 / N) sum over photons y_p within r of x of K(|y_p - x|) f(wo, wi_p) beta_p
//
// at the price of a blur of radius r (the kernel's bias, kernel.h). Three estimators use it:
//   pm   photon mapping (Jensen 1996): the camera path through mirrors and glass to its first
//        diffuse vertex x; there the direct light by next-event estimation (lesson 3's light
//        sample) and all the light that has bounced at least once by the photons; a fixed
//        radius, so the image converges to the blurred answer (biased);
//   ppm  progressive photon mapping in the probabilistic form of Knaus and Zwicker (2011): pass
//        k = 1, 2, ... (sample index k - 1 of every pixel) is an independent photon-mapping
//        estimate with radius r_k = r_1 k^((alpha - 1) / 2), 0 < alpha < 1; the film's average over
//        the passes has a bias and a variance that both vanish (consistent);
//   vcm  vertex connection and merging (Georgiev et al. 2012; Hachisuka et al. 2012): every
//        strategy of lesson 5 and a merge at every diffuse vertex of the camera path, each
//        weighted by MIS over all of them (merge_weights.h: a merge is strategy j's density
//        times p_L(x_j) N pi r^2, counted in lesson 5's weights through its hook for an extra
//        technique), with the progressive radius;
//   bpt  vcm without merging: lesson 5 itself, bit for bit;
//   vpl  instant radiosity (Keller 1997): the light subpaths' vertices as virtual point lights,
//        *connected* to the first diffuse camera vertex rather than merged with it (vpl.h).
// Pass k's photons come from N = width x height light subpaths (vpl: --vpls) drawn from (seed, k, subpath)
// (photons.h), traced before the pass (begin_pass), so the image is the same for any number of
// threads and any split of the passes across parts of a render (docs/farm.md). vcm joins each
// pixel's camera subpath to the pass's light subpath of the pixel's index, as Georgiev et al.
// do: one set of light subpaths serves the joins and the merges (bpt traces its own, as lesson 5).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <utility>

#include "05_bidirectional/bidirectional.h"
#include "06_photon_mapping/kernel.h"
#include "06_photon_mapping/merge_weights.h"
#include "06_photon_mapping/photon_map.h"
#include "06_photon_mapping/photons.h"
#include "06_photon_mapping/vpl.h"
#include "render/model.h"

namespace lessons {

enum class PhotonMethod { PhotonMapping, Progressive, Bidirectional, VertexMerging, VirtualLights };

// The methods by name (the --method flag's choices).
inline constexpr std::pair<const char*, PhotonMethod> kPhotonMethodNames[] = {
    {"pm", PhotonMethod::PhotonMapping},
    {"ppm", PhotonMethod::Progressive},
    {"bpt", PhotonMethod::Bidirectional},
    {"vcm", PhotonMethod::VertexMerging},
    {"vpl", PhotonMethod::VirtualLights}};
const char* photon_method_name(PhotonMethod m);

// Where vcm merges (--merging): `auto` only in a scene with a delta surface (a mirror, smooth
// glass), the only place a path can need a merge (a light path that reaches a diffuse surface
// through a delta vertex, seen through another: L S+ D S+ E, which no join can make); in any
// other scene every path has a join, and vcm is bpt, lesson 5 bit for bit. `always` merges
// everywhere (to see what merging costs where nothing needs it); `never` is bpt.
enum class Merging { Auto, Always, Never };
inline constexpr std::pair<const char*, Merging> kMergingNames[] = {
    {"auto", Merging::Auto}, {"always", Merging::Always}, {"never", Merging::Never}};
// Whether vcm merges in a scene under `merging`: always, never, or (auto) where it has a delta
// surface.
bool merges_in(const Scene& scene, Merging merging);

// Light subpaths per pass for vpl: each pixel sample joins every one of their virtual lights, so
// a sample's cost grows with it, while fewer per pass means more passes, each with lights of its
// own, in the same time. 16 gives about 36 virtual lights per pass in the Cornell box with
// spheres; there 4 and 16 reach the same error in 20 s and 64 a larger one (docs/06_photon_mapping.md).
inline constexpr int kDefaultVplPaths = 16;

struct PhotonOptions {
    PhotonMethod method = PhotonMethod::VertexMerging;
    BidirOptions paths;   // path length and Russian roulette, for both subpaths (lesson 5's)
    float radius = 0.0f;  // r_1, in scene units; 0: default_photon_radius (radius.h)
    float alpha = 0.0f;   // the radius's exponent; 0: the method's default (kDefaultAlpha)
    Kernel kernel = Kernel::Constant;
    Merging merging = Merging::Auto;  // where vcm merges (kMergingNames)
    bool technique_layers = false;    // layers: the light carried by each kind of technique
    double max_photon_mb = 4096.0;    // the most memory one pass's photons may take
    // Instant radiosity (vpl.h): light subpaths per pass, the cap on G (< 0: default_vpl_clamp;
    // 0: none), and whether to compensate for it.
    int vpls = kDefaultVplPaths;
    float vpl_clamp = -1.0f;
    bool vpl_compensate = false;
};

// The radius of pass k (k = 0, 1, ...): r_1 (k + 1)^((alpha - 1) / 2). alpha = 1 keeps it.
float pass_radius(float r1, float alpha, int k);
// The method's alpha when none is given: 1 for pm (a fixed radius), 2/3 for ppm (Knaus and
// Zwicker's choice: the fastest the MSE can fall, N^(-2/3)), 3/4 for vcm (Georgiev et al.'s).
float default_alpha(PhotonMethod m);

// One pass's photons: its radius, the light subpaths and their photons in a grid.
struct PhotonPass {
    int index = -1;
    uint64_t seed = 0;
    float radius = 0.0f;
    LightPaths paths;
    PhotonGrid grid;                           // pm, ppm, vcm
    std::vector<VirtualLight> virtual_lights;  // vpl: into paths
    size_t bytes() const {
        return paths.bytes() + grid.bytes() + virtual_lights.size() * sizeof(VirtualLight);
    }
};

// Photon mapping at the first diffuse vertex (pm and ppm): one sample of the pixel of `ray`.
// layers (if not empty): [0] emission and direct light, [1] the photons.
Color photon_mapping(const Bidir& b, const PhotonPass& pass, const Ray& ray, Rng& rng,
                     const PhotonOptions& options, std::span<Color> layers);

// Vertex connection and merging's step after tracing a pass: each photon's light side of the
// merge's weight (merge_light_side, merge_weights.h, at eta = N pi r^2), computed once, from its
// light subpath's vertices; the photons no merge can use (their weight is 0) are left out.
void weigh_photons(const Bidir& b, LightPaths& paths, double eta, int threads);
// The light side as a weighed photon holds it (two floats: the roots of its terms), and back.
void store_light_side(Photon& photon, const MergeLightSide& side);
MergeLightSide light_side_of(const Photon& photon);
// The weight of merging weighed photon p at the camera vertex of `camera` (its camera side,
// merge_camera_side), whose BSDF is `bsdf`: merge_weight with the two densities of scattering
// there, the photon's arrival direction p.wi standing for the direction towards x_{s-1}.
float merge_weight(const Photon& p, const MergeCameraSide& camera, const Bsdf& bsdf);

// The merges of a camera subpath with the pass's (weighed) photons (vcm): the sum over every
// vertex z_{t-1} (t >= 2) that scatters by a non-delta BSDF and every photon within r of it of
//   w_merge (1 / N) K f(z) beta_L beta_C,
// w_merge from merge_weights.h with eta = N pi r^2, its camera side computed once per vertex.
Color merges(const PhotonPass& pass, std::span<const Vertex> camera, const PhotonOptions& options);

// Lesson 6 as a model the render loop runs. `scene` must outlive it.
class PhotonMappingModel final : public Model {
public:
    // vcm where it does not merge (merges_in) is made as bpt, and says so in its notes.
    PhotonMappingModel(const Scene& scene, const PhotonOptions& options);
    // Lesson 6 renders pass by pass (its photons are the pass's; vcm's pixel takes the pass's
    // light subpath of its index); bpt and vcm splat, pm and ppm do not.
    Color sample(const Ray& ray, Rng& rng, uint32_t pixel, std::span<Color> layers,
                 std::vector<Splat>& splats) const override;
    void begin_pass(int sample_index, const RenderSettings& settings) const override;
    uint64_t pass_rays() const override { return rays_; }
    void report(Report& report) const override;

    float alpha() const { return alpha_; }
    float vpl_clamp() const { return clamp_; }

private:
    void add_what_it_misses(const Scene& scene);
    void add_vpl_notes(const Scene& scene);
    void add_bpt_notes(const Scene& scene, const PhotonOptions& options);
    Color connect_and_merge(const Ray& ray, Rng& rng, uint32_t pixel, std::span<Color> layers,
                            std::vector<Splat>& splats) const;

    LightSampler lights_;
    Bidir b_;                // refers to lights_
    PhotonOptions options_;  // with the method it runs (vcm that does not merge: bpt)
    PhotonMethod asked_;     // the method asked for (the report's "method")
    float r1_ = 0.0f, alpha_ = 1.0f;
    float clamp_ = 0.0f;  // vpl's cap on G
    // The current pass's photons (begin_pass) and what the report says of the passes (summed over
    // every render of this model: the command line makes one model per run).
    mutable PhotonPass pass_;
    mutable uint64_t rays_ = 0;
    mutable size_t most_bytes_ = 0;
    mutable uint64_t photons_ = 0;
    mutable int passes_ = 0, first_pass_ = -1, last_pass_ = -1;
};

}  // namespace lessons
