// Sampling an area light (see lights.h): for a shading point, a point on it, by solid angle
// where that can be done accurately (a rectangle, a sphere seen from outside) and by area
// otherwise, and the density of such a point per sr (area_pdf); for a light subpath, a point
// by area and a direction by cosine (sample_area_emission). Choosing the light is in
// lights.cpp.
#include <algorithm>
#include <cmath>

#include "lights/lights.h"
#include "sampling/sampling.h"

namespace lessons {

namespace {

// 1 - cos(theta_max) of the cone a sphere subtends, sin^2(theta_max) = r^2 / d^2, written as
// sin^2 / (1 + cos) so that small, far spheres keep their precision.
float cone_one_minus_cos(float sin2_max) {
    return sin2_max / (1.0f + std::sqrt(std::max(0.0f, 1.0f - sin2_max)));
}

// The unit normal of the point a sphere light is sampled at, seen from outside: a direction
// uniform in the cone of half-angle theta_max the sphere subtends (sin(theta_max) = r / d,
// sin2_max its square), then the point where it first meets the sphere, seen from the center
// at angle alpha from the axis, with
//   cos(alpha) = sin^2(theta) / sin(theta_max) + cos(theta) sqrt(1 - sin^2(theta) /
//   sin^2(theta_max)).
// The normal points back towards the shading point's side of the sphere; to_center runs from
// the shading point to the center.
Vec3 normal_in_cone(const Vec3& to_center, float sin2_max, float one_minus_cos_max, const Vec2& u) {
    const float sin_max = std::sqrt(sin2_max);
    const float one_minus_cos = u.x * one_minus_cos_max;
    const float sin2 = one_minus_cos * (2.0f - one_minus_cos);
    const float cos_theta = 1.0f - one_minus_cos;
    const float cos_alpha =
        sin2 / sin_max + cos_theta * std::sqrt(std::max(0.0f, 1.0f - sin2 / sin2_max));
    const float sin_alpha = std::sqrt(std::max(0.0f, 1.0f - cos_alpha * cos_alpha));
    const float phi = 2.0f * kPi * u.y;
    const Frame frame(glm::normalize(to_center));
    return glm::normalize(
        frame.to_world(-Vec3(sin_alpha * std::cos(phi), sin_alpha * std::sin(phi), cos_alpha)));
}

}  // namespace

std::vector<std::optional<Rectangle>> LightSampler::solid_angle_rectangles(const Scene& scene) {
    std::vector<std::optional<Rectangle>> rectangles;
    for (const AreaLight& light : scene.area_lights()) {
        rectangles.push_back(std::nullopt);
        if (light.rectangle) {
            const Quad& quad = scene.quads()[light.prim.index()];
            rectangles.back().emplace(quad.corner, quad.edge_u, quad.edge_v);
        }
    }
    return rectangles;
}

std::optional<LightSample> LightSampler::sample_area(uint32_t area_light, const SurfacePoint& at,
                                                     const Vec2& u, float choose) const {
    const AreaLight& light = scene_.area_lights()[area_light];
    const LightPoint on = light.prim.kind() == ShapeKind::Sphere
                              ? point_on_sphere_light(area_light, at.p, u)
                              : point_on_flat_light(area_light, at.p, u);
    const Vec3 &q = on.point.p, &n_q = on.point.n;
    float pdf_solid_angle = on.pdf_solid_angle;

    Vec3 d = q - at.p;
    const float d2 = glm::dot(d, d);
    if (!(d2 > 0.0f)) return std::nullopt;
    const float distance = std::sqrt(d2);
    const Vec3 wi = d / distance;
    float cos_light = glm::dot(n_q, -wi);  // > 0: the light's front faces the point
    if (scene_.naive.light_abs_cosine) cos_light = std::fabs(cos_light);  // the textbook slip
    if (cos_light <= 0.0f && !light.two_sided) return std::nullopt;       // one-sided: dark behind
    if (on.by_area) pdf_solid_angle = area_to_solid_angle_pdf(1.0f / light.area, d2, cos_light);
    if (!(pdf_solid_angle > 0.0f) || !std::isfinite(pdf_solid_angle)) return std::nullopt;
    return LightSample{light.radiance,
                       wi,
                       distance,
                       pdf_solid_angle * choose,
                       false,
                       spawn_ray_between(at, on.point),
                       light.prim,
                       q,
                       n_q};
}

LightSampler::LightPoint LightSampler::point_on_sphere_light(uint32_t area_light, const Vec3& p,
                                                             const Vec2& u) const {
    const Sphere& s = scene_.spheres()[scene_.area_lights()[area_light].prim.index()];
    LightPoint on;
    const Vec3 to_center = s.center - p;
    const float d2 = glm::dot(to_center, to_center);
    const float r2 = s.radius * s.radius;
    if (d2 <= r2 * 1.0001f) {
        // From inside (or on) the sphere, sample its whole area: p_A = 1 / (4 pi r^2).
        const SurfacePoint by_area = point_by_area(area_light, u);
        on.point.p = by_area.p;
        on.point.n = by_area.n;
        const Vec3 d = on.point.p - p;
        on.pdf_solid_angle = area_to_solid_angle_pdf(1.0f / s.area(), glm::dot(d, d),
                                                     glm::dot(on.point.n, glm::normalize(-d)));
    } else {
        // Seen from outside: uniform in the cone the sphere subtends.
        const float sin2_max = r2 / d2;
        const float one_minus_cos_max = cone_one_minus_cos(sin2_max);
        on.point.n = normal_in_cone(to_center, sin2_max, one_minus_cos_max, u);
        on.point.p = s.point_at(on.point.n).p;
        on.pdf_solid_angle = uniform_cone_pdf(one_minus_cos_max);
    }
    on.point.error = s.point_at(on.point.n).error;
    return on;
}

LightSampler::LightPoint LightSampler::point_on_flat_light(uint32_t area_light, const Vec3& p,
                                                           const Vec2& u) const {
    LightPoint on;
    on.by_area = true;
    Vec2 ab = u;  // a quad's edge coordinates of the point, uniform by area
    if (const std::optional<Rectangle>& rectangle = rectangles_[area_light]) {
        const SphericalRectangle rect(p, *rectangle);
        if (rect.well_conditioned()) {
            ab = rect.sample(u);  // uniform in solid angle instead
            on.pdf_solid_angle = spherical_rectangle_pdf(rect);
            on.by_area = false;
        }
    }
    on.point = point_by_area(area_light, ab);
    return on;
}

SurfacePoint LightSampler::point_by_area(uint32_t area_light, const Vec2& u) const {
    const AreaLight& light = scene_.area_lights()[area_light];
    const PrimRef prim = light.prim;
    switch (prim.kind()) {
        case ShapeKind::Sphere: {
            const Sphere& s = scene_.spheres()[prim.index()];
            return s.point_at(sample_uniform_sphere(u));
        }
        case ShapeKind::Quad: {
            const Quad& quad = scene_.quads()[prim.index()];
            return {quad.corner + u.x * quad.edge_u + u.y * quad.edge_v,
                    gamma_bound(4) * (glm::abs(quad.corner) + glm::abs(u.x * quad.edge_u) +
                                      glm::abs(u.y * quad.edge_v)),
                    quad.normal};
        }
        case ShapeKind::Triangle: {
            const Triangle& t = scene_.triangles()[prim.index()];
            const Vec3 &p0 = scene_.positions()[t.v[0]], &p1 = scene_.positions()[t.v[1]],
                       &p2 = scene_.positions()[t.v[2]];
            const Vec2 b = sample_uniform_triangle(u);
            const float b0 = 1.0f - b.x - b.y;
            return {b0 * p0 + b.x * p1 + b.y * p2,
                    gamma_bound(7) * (glm::abs(b0 * p0) + glm::abs(b.x * p1) + glm::abs(b.y * p2)),
                    light.normal};
        }
    }
    return {};
}

float LightSampler::area_pdf(uint32_t area_light, const Vec3& p, const Vec3& q,
                             const Vec3& n_q) const {
    const AreaLight& light = scene_.area_lights()[area_light];
    const Vec3 d = q - p;
    const float d2 = glm::dot(d, d);
    if (!(d2 > 0.0f)) return 0.0f;
    float cos_light = glm::dot(n_q, -d / std::sqrt(d2));
    if (scene_.naive.light_abs_cosine) cos_light = std::fabs(cos_light);
    if (cos_light <= 0.0f && !light.two_sided) return 0.0f;
    if (light.prim.kind() == ShapeKind::Sphere) {
        const Sphere& s = scene_.spheres()[light.prim.index()];
        const Vec3 to_center = s.center - p;
        const float dc2 = glm::dot(to_center, to_center);
        const float r2 = s.radius * s.radius;
        if (dc2 <= r2 * 1.0001f) return area_to_solid_angle_pdf(1.0f / s.area(), d2, cos_light);
        const float sin2_max = r2 / dc2;
        return uniform_cone_pdf(cone_one_minus_cos(sin2_max));
    }
    if (const std::optional<Rectangle>& rectangle = rectangles_[area_light]) {
        const SphericalRectangle rect(p, *rectangle);
        if (rect.well_conditioned()) return spherical_rectangle_pdf(rect);
    }
    return area_to_solid_angle_pdf(1.0f / light.area, d2, cos_light);
}

// Emission from an area light for a light subpath: a point by area, a direction by cosine.
std::optional<EmissionSample> LightSampler::sample_area_emission(uint32_t area_light, float choose,
                                                                 const Vec2& u_point,
                                                                 const Vec2& u_dir) const {
    const AreaLight& light = scene_.area_lights()[area_light];
    SurfacePoint on = point_by_area(area_light, u_point);
    // A two-sided light leaves by either side, half the time each: u_dir.x picks the side, then
    // is stretched back to [0, 1).
    Vec2 u = u_dir;
    float side = 1.0f;
    if (light.two_sided) {
        side = 0.5f;
        if (u.x < 0.5f) {
            on.n = -on.n;
            u.x = 2.0f * u.x;
        } else {
            u.x = std::min(2.0f * u.x - 1.0f, 0x1.fffffep-1f);
        }
    }
    const Vec3 local = sample_cosine_hemisphere(u);
    if (!(local.z > 0.0f)) return std::nullopt;  // the disk's rim: measure zero
    const Vec3 w = glm::normalize(Frame(on.n).to_world(local));
    return EmissionSample{spawn_ray(on, w),
                          on.p,
                          on.n,
                          light.radiance,
                          choose / light.area,
                          side * cosine_hemisphere_pdf(local.z),
                          light.prim,
                          on.error};
}

}  // namespace lessons
