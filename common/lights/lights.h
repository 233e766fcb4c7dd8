// Light sampling for lessons 3 to 5: choose a light, then a point on it, and say how likely
// that choice was, per unit solid angle as seen from the shading point.
//
// Lights: point lights (intensity I, W/sr; a spot's fades with its cone), directional lights
// (irradiance E, W/m^2, from one direction), emissive surfaces (radiance L_e; quads, triangles
// and spheres, one-sided unless the material says two-sided), and the uniform environment
// (the scene's background radiance). A light is chosen with probability proportional to its
// power (though none of positive power less often than 2^-24: sampling/discrete.h); then
//   rectangles (quads with orthogonal edges): a direction uniform in the solid angle they
//     subtend (SphericalRectangle, sampling.h), p = 1 / Omega, which stays bounded near the
//     light's plane, where area sampling's 1 / (d^2 cos(theta_l)) does not (by area when the
//     solid angle is too small or too large to sample accurately);
//   other quads, triangles: a point uniform by area, p_A = 1 / A, converted to solid angle;
//   spheres: a direction uniform in the cone the sphere subtends (from inside: by area);
//   environment: a uniform sky, a direction uniform on the sphere, 1 / (4 pi); a map, by its
//     importance, luminance times sin(theta) per texel (scene/environment.h);
//   point and spot lights: their position (a delta distribution);
//   directional lights: their direction (a delta distribution too).
#pragma once

#include <optional>
#include <unordered_map>
#include <vector>

#include "geometry/math.h"
#include "geometry/spawn.h"
#include "sampling/sampling.h"
#include "scene/scene.h"

namespace lessons {

// The one conversion of an area density into a solid-angle density , written once: a patch dA at
// distance d, tilted by theta_l from the direction back to the shading point, subtends
// d(omega) = cos(theta_l) dA / d^2, so p_omega = p_A d^2 / |cos(theta_l)|.
inline float area_to_solid_angle_pdf(float pdf_area, float distance_squared, float cos_light) {
    const float c = std::fabs(cos_light);
    return c > 0.0f ? pdf_area * distance_squared / c : 0.0f;
}
// And back, for a direction sampled at the shading point that reaches a patch at distance d,
// tilted by theta: p_A = p_omega |cos(theta)| / d^2 (lesson 4 weighs path vertices per area).
inline float solid_angle_to_area_pdf(float pdf_solid_angle, float distance_squared,
                                     float cos_theta) {
    return distance_squared > 0.0f ? pdf_solid_angle * std::fabs(cos_theta) / distance_squared
                                   : 0.0f;
}

struct LightSample {
    // Radiance arriving at the shading point from the sampled light point, W/(sr m^2). For a
    // point light (is_delta), the irradiance it gives a surface facing it, I / d^2, W/m^2 (a
    // spot's I along wi); for a directional light, its irradiance E.
    Color radiance;
    Vec3 wi;         // unit direction from the shading point to the light
    float distance;  // to the sampled point; infinite for the environment and directional lights
    float pdf;       // solid-angle density of wi, times the probability of choosing the light;
                     // for a point or directional light: that probability alone
    bool is_delta;   // a point or directional light: no BSDF sample can ever hit it
    Ray shadow_ray;  // the segment that must be unoccluded (robustly offset at both ends)
    std::optional<PrimRef> emitter;  // the primitive the segment ends on, which cannot block it
    Vec3 point{0.0f}, normal{0.0f};  // on an area light: the sampled point and its unit normal
    // A point or directional light's index, into scene.point_lights() or directional_lights().
    uint32_t light_index = 0;
    bool directional = false;
};

// Light leaving a light, for light paths (lesson 5): a light chosen by power as sample() chooses,
// then
//   an area light: a point uniform by area on it, and a direction distributed as cos(theta)
//     about the emitting side's normal (either side of a two-sided light, half the time each);
//   a point light: its position, and a direction uniform on the sphere (a spot: in its cone);
//   a directional light: its direction, from a point uniform on the disk, facing it, that the
//     scene's bounding sphere shows it (radius R, centred on the sphere's centre and placed
//     just outside it), so every ray of its light that meets the scene starts on the disk.
// The environment starts none (lesson 5 says why).
struct EmissionSample {
    Ray ray;         // leaving the light
    Vec3 point;      // where it leaves
    Vec3 normal;     // unit geometric normal there, on the side the ray leaves (zero: point
                     // light; a directional light's: its direction of travel)
    Color radiance;  // L_e along the ray, W/(sr m^2); for a point light its intensity I along
                     // the ray, W/sr; for a directional light its irradiance E, W/m^2
    float pdf_area;  // density of the point: choice probability / area, per m^2 (point and
                     // directional lights: the choice probability alone, a discrete choice of
                     // a delta position or direction)
    float pdf_dir;   // density of the direction, per sr (a directional light: of the point on
                     // its disk, per m^2 across the beam: 1 / (pi R^2))
    std::optional<PrimRef> emitter;  // the emissive primitive; none for point/directional lights
    Vec3 error{0.0f};                // bound on the rounding error of `point` (for rays to it)
    bool directional = false;        // from a directional light
    uint32_t light_index = 0;        // a point or directional light's, as in LightSample
    bool is_delta() const { return !emitter; }
};

class LightSampler {
public:
    explicit LightSampler(const Scene& scene);

    bool empty() const { return lights_.empty(); }
    size_t size() const { return lights_.size(); }
    // Whether some light is a delta one: a point, spot or directional light that no BSDF-sampled
    // direction can find.
    bool has_delta_lights() const { return has_delta_lights_; }

    // A light sample for the shading point `at`, from three uniform numbers. None if the
    // scene has no lights, or the sampled point cannot send light to `at` (e.g. the back of a
    // one-sided light).
    std::optional<LightSample> sample(const SurfacePoint& at, float u_choose, const Vec2& u) const;

    // The density sample() has of producing direction wi that reaches the emissive surface
    // `light_hit` (found by tracing a ray from p): for weighting BSDF samples that hit lights.
    float pdf(const Vec3& p, const SurfaceInteraction& light_hit) const;
    // The same for the point q (unit geometric normal n_q) of the emissive primitive `light`.
    float pdf(const Vec3& p, PrimRef light, const Vec3& q, const Vec3& n_q) const;
    // The same for unit direction `dir` escaping to the environment (a map's importance, or
    // uniform on the sphere for a uniform sky).
    float environment_pdf(const Vec3& dir) const;

    // A ray of light leaving a light, from five uniform numbers (see EmissionSample).
    std::optional<EmissionSample> sample_emission(float u_choose, const Vec2& u_point,
                                                  const Vec2& u_dir) const;
    // The densities sample_emission() has of leaving the emitter `light` from its point q, where
    // its unit geometric normal is n_q, in direction w (unit): per m^2 of the light and per sr.
    struct EmissionPdf {
        float area = 0.0f, dir = 0.0f;
    };
    EmissionPdf emission_pdf(PrimRef light, const Vec3& n_q, const Vec3& w) const;
    // The same for point light `index` (into scene.point_lights()) sending light along unit
    // direction w: its choice probability, and the uniform sphere's 1 / (4 pi) (a spot: the
    // uniform cone's, within its cone).
    EmissionPdf point_emission_pdf(uint32_t index, const Vec3& w) const;
    // The same for directional light `index` (into scene.directional_lights()): its choice
    // probability, and per m^2 across its beam, 1 / (pi R^2) (sample_emission's disk).
    EmissionPdf directional_emission_pdf(uint32_t index) const;
    // The radius R of the disk that directional lights start their light from (lights.h).
    float beam_radius() const { return beam_radius_; }
    // Where on the plane of that disk (for light travelling along unit `direction`) the ray
    // starts that passes through `through`.
    Vec3 beam_origin(const Vec3& direction, const Vec3& through) const {
        const float along = glm::dot(through - beam_center_, direction) + 1.001f * beam_radius_;
        return through - along * direction;
    }

private:
    // The light a uniform number picks, in proportion to power (an index into lights_).
    size_t choose_light(float u_choose) const;
    float choice_probability(size_t light) const;
    // The area lights' part (area_light.cpp). Each takes an index into scene.area_lights().
    // sample_area's density is per sr times `choose`, the probability of choosing the light.
    std::optional<LightSample> sample_area(uint32_t area_light, const SurfacePoint& at,
                                           const Vec2& u, float choose) const;
    float area_pdf(uint32_t area_light, const Vec3& p, const Vec3& q, const Vec3& n_q) const;
    // A point sample_area chose on an area light for the shading point: the light's surface
    // point with its unit normal, and its density per sr; or, by_area, a point uniform by area,
    // whose density 1 / area sample_area converts once it knows the distance and the angle.
    struct LightPoint {
        SurfacePoint point;
        float pdf_solid_angle = 0.0f;
        bool by_area = false;
    };
    // A sphere's point for the shading point p: uniform in the cone the sphere subtends, or by
    // area from inside it (with its density per sr either way).
    LightPoint point_on_sphere_light(uint32_t area_light, const Vec3& p, const Vec2& u) const;
    // A quad's or triangle's: uniform in the solid angle of a rectangle (rectangles_) where that
    // is well conditioned, else by area.
    LightPoint point_on_flat_light(uint32_t area_light, const Vec3& p, const Vec2& u) const;
    // A point uniform by area on an area light: the light's surface point, with its unit normal.
    SurfacePoint point_by_area(uint32_t area_light, const Vec2& u) const;
    // Per area light of the scene: its rectangle if it is sampled by solid angle (rectangles_).
    static std::vector<std::optional<Rectangle>> solid_angle_rectangles(const Scene& scene);
    // A ray leaving area light `area_light`, chosen with probability `choose` (sample_emission).
    std::optional<EmissionSample> sample_area_emission(uint32_t area_light, float choose,
                                                       const Vec2& u_point,
                                                       const Vec2& u_dir) const;

    const Scene& scene_;
    // The scene's lights (Scene::lights()) but the point and area lights that send nothing.
    std::vector<LightRef> lights_;
    std::vector<float> cdf_;  // cumulative choice probabilities (sampling/discrete.h)
    std::unordered_map<uint32_t, size_t> light_of_primitive_;
    std::vector<size_t> light_of_point_;  // per point light: its index in lights_, or SIZE_MAX
    std::vector<size_t> light_of_directional_;  // the same per directional light
    // Per area light: its rectangle, for those sampled by solid angle (AreaLight::rectangle).
    std::vector<std::optional<Rectangle>> rectangles_;
    std::optional<size_t> environment_;
    bool has_delta_lights_ = false;
    // The scene's bounding sphere: a directional light's beam covers it (sample_emission).
    Vec3 beam_center_{0.0f};
    float beam_radius_ = 1.0f;
};

}  // namespace lessons
