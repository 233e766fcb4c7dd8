// Lesson 5, section 1: camera and light subpaths (see subpaths.h).
#include "05_bidirectional/subpaths.h"

#include <algorithm>
#include <cmath>

#include "04_rendering_equation/rendering_equation.h"
#include "sampling/rng.h"
#include "sampling/sampling.h"

namespace lessons {

Vec3 direction(const Vertex& from, const Vertex& to) {
    if (to.infinite || to.directional) return to.p;
    if (from.directional) return -from.p;
    return glm::normalize(to.p - from.p);
}

float to_area_density(float pdf_solid_angle, const Vertex& from, const Vertex& to) {
    if (to.infinite || to.directional) return pdf_solid_angle;
    if (from.directional)  // parallel light: no spreading with distance
        return to.n == Vec3(0.0f) ? pdf_solid_angle
                                  : pdf_solid_angle * std::fabs(glm::dot(to.n, from.p));
    const Vec3 d = to.p - from.p;
    const float d2 = glm::dot(d, d);
    // A point (the camera, a point light) has no surface to tilt: its "cosine" is 1.
    const float cos_to = to.n == Vec3(0.0f) ? 1.0f : glm::dot(to.n, d) / std::sqrt(d2);
    return solid_angle_to_area_pdf(pdf_solid_angle, d2, cos_to);
}

glm::ivec2 pixel_at(const Bidir& b, const Vec2& raster) {
    return {std::min(static_cast<int>(raster.x), b.width - 1),
            std::min(static_cast<int>(raster.y), b.height - 1)};
}

float light_origin_density(const Bidir& b, const Vertex& v) {
    if (v.infinite) return b.lights.environment_pdf(v.p);                  // its direction
    if (v.type == VertexType::Light && v.delta_light()) return v.pdf_fwd;  // set when sampled
    const std::optional<PrimRef> prim = v.primitive();
    return prim ? b.lights.emission_pdf(*prim, v.n, v.n).area : 0.0f;
}

float light_sample_density(const Bidir& b, const Vertex& v, const Vertex& from) {
    const std::optional<PrimRef> prim = v.primitive();
    if (v.infinite || v.delta_light() || !prim) return light_origin_density(b, v);
    const Vec3 n = v.type == VertexType::Light || glm::dot(v.n, v.si.wo) > 0.0f ? v.n : -v.n;
    return to_area_density(b.lights.pdf(from.p, *prim, v.p, n), from, v);
}

float light_emission_density(const Bidir& b, const Vertex& v, const Vertex& next) {
    if (v.infinite) return 0.0f;  // the environment starts no light subpath
    const Vec3 w = direction(v, next);
    float pdf_dir = 0.0f;
    if (v.point_light) {
        pdf_dir = b.lights.point_emission_pdf(v.light_index, w).dir;
    } else if (v.directional) {
        pdf_dir = b.lights.directional_emission_pdf(v.light_index).dir;
    } else {
        const std::optional<PrimRef> prim = v.primitive();
        // The emitting side: a light vertex's normal is on it; a camera vertex on an emitter saw
        // its front from the side it arrived.
        const Vec3 n = v.type == VertexType::Light || glm::dot(v.n, v.si.wo) > 0.0f ? v.n : -v.n;
        if (prim) pdf_dir = b.lights.emission_pdf(*prim, n, w).dir;
    }
    return to_area_density(pdf_dir, v, next);
}

float density_towards(const Bidir& b, const Vertex& v, const Vertex* previous, const Vertex& next) {
    switch (v.type) {
        case VertexType::Camera:
            return to_area_density(b.camera.importance(direction(v, next)), v, next);
        case VertexType::Light: return light_emission_density(b, v, next);
        case VertexType::Surface:
            if (!previous || v.delta) return 0.0f;
            {  // a subpath arriving from `previous` samples with the BSDF as seen from there
                const Vec3 from = direction(v, *previous);
                return to_area_density(v.bsdf->pdf_seen_from(from, direction(v, next)), v, next);
            }
    }
    return 0.0f;
}

namespace {

// Light arrives at v from si.wo and leaves along w. With a shading normal n_s other than the
// geometric n_g, f |w . n_s| (what the camera side uses) is not its own adjoint; the light side
// needs f |wo . n_s| |w . n_g| / |wo . n_g| instead: this factor times |w . n_s|.
float adjoint_shading_correction(const Bidir& b, const Bsdf& bsdf, const Vertex& v, const Vec3& w) {
    if (b.scene.naive.no_adjoint_correction) return 1.0f;  // --naive adjoint: to see it fail
    const Vec3& wo = v.si.wo;
    const float num = bsdf.abs_cos(wo) * std::fabs(glm::dot(w, v.si.n_geo));
    const float den = std::fabs(glm::dot(wo, v.si.n_geo)) * bsdf.abs_cos(w);
    return den > 0.0f ? num / den : 0.0f;
}

}  // namespace

Color light_side_scattering(const Bidir& b, const Vertex& v, const Vec3& w) {
    // The scene's BSDF at a vertex is the one its camera side sees (Bsdf::seen_from): here w.
    const Bsdf seen = v.bsdf->seen_from(w);
    return seen.eval(v.si.wo, w) * (adjoint_shading_correction(b, seen, v, w) * seen.abs_cos(w));
}

namespace {

// The vertex a camera subpath ends on when its ray escapes into a sky: the direction, with the
// density per steradian the previous vertex sampled it with (a vertex at infinity has no area).
Vertex sky_vertex(const Bidir& b, const Ray& ray, const Color& beta, float pdf_dir,
                  const Vertex& previous) {
    Vertex sky;
    sky.type = VertexType::Light;
    sky.infinite = true;
    sky.p = ray.dir;
    sky.beta = beta;
    sky.pdf_fwd = pdf_dir;
    sky.pdf_light_sample = light_sample_density(b, sky, previous);
    return sky;
}

// The vertex where `ray`, sent from `previous` with solid-angle density pdf_dir, hits the scene:
// its hit, BSDF, throughput and density per unit area; on a camera subpath, an emitter also
// keeps the density with which a light sample at `previous` would have picked it.
Vertex surface_vertex(const Bidir& b, const Ray& ray, const Hit& hit, const Color& beta,
                      float pdf_dir, const Vertex& previous, Transport transport) {
    Vertex v;
    v.si = b.scene.interaction(ray, hit);
    v.p = v.si.p;
    v.n = v.si.n_geo;
    v.bsdf.emplace(b.scene.material(v.si.material), v.si);
    v.beta = beta;
    v.pdf_fwd = to_area_density(pdf_dir, previous, v);
    if (transport == Transport::Radiance && previous.type == VertexType::Surface &&
        b.scene.material(v.si.material).is_emissive())
        v.pdf_light_sample = light_sample_density(b, v, previous);
    return v;
}

// Extends a subpath whose last vertex sent `ray` with solid-angle density pdf_dir and
// throughput beta: lesson 4's loop, keeping every vertex and both of its densities. Light
// subpaths carry importance through glass (Transport::Importance) and the shading-normal
// correction; camera subpaths carry radiance. `scatter(vertex)` picks the next direction: the
// BSDF's sample in the lesson's walks (and the path given to subpaths_along, below).
template <class Scatter>
void walk(const Bidir& b, Ray ray, Color beta, float pdf_dir, RandomNumbers& rng, int max_vertices,
          int roulette_after, Transport transport, std::vector<Vertex>& path, Scatter&& scatter) {
    const Color beta_start = beta;
    for (int bounce = 0; static_cast<int>(path.size()) < max_vertices; ++bounce) {
        const std::optional<Hit> hit = b.scene.intersect(ray);
        if (!hit) {
            // The camera path escapes: a last vertex at the sky, if there is one.
            if (transport == Transport::Radiance && b.scene.has_environment())
                path.push_back(sky_vertex(b, ray, beta, pdf_dir, path.back()));
            return;
        }
        path.push_back(surface_vertex(b, ray, *hit, beta, pdf_dir, path.back(), transport));
        Vertex& here = path.back();
        Vertex& before = path[path.size() - 2];
        if (static_cast<int>(path.size()) >= max_vertices) return;

        const std::optional<BsdfSample> s = scatter(here);
        if (!s) return;
        Color weight = s->f * here.bsdf->abs_cos(s->wi) / s->pdf;  // f cos / p, as in lesson 4
        // The light side's f cos, as the camera side sees it (a mirror or glass keeps the frame
        // it was made with: its reflection is no other).
        if (transport == Transport::Importance)
            weight = s->is_delta ? weight * adjoint_shading_correction(b, *here.bsdf, here, s->wi)
                                 : light_side_scattering(b, here, s->wi) / s->pdf;
        // The density of the way back: `before` sampled from here, by a subpath that arrived
        // from the new direction (and so sees the BSDF from there).
        float pdf_back = here.bsdf->pdf_seen_from(s->wi, here.si.wo);
        float pdf_next = s->pdf;
        if (s->is_delta) {
            // A delta choice is made the same way from either side: the weights leave it out.
            here.delta = true;
            pdf_back = pdf_next = 0.0f;
        }
        before.pdf_rev = to_area_density(pdf_back, here, before);
        beta *= weight;
        if (is_black(beta) || !is_finite(beta)) return;
        // Russian roulette on the throughput relative to the subpath's start (lesson 4's rule).
        if (roulette_after >= 0 && bounce >= roulette_after) {
            const float q = russian_roulette_survival(beta / max_component(beta_start));
            if (rng.uniform() >= q) return;
            beta /= q;
        }
        pdf_dir = pdf_next;
        ray = spawn_ray(here.si.surface_point(), s->wi);
    }
}

void random_walk(const Bidir& b, const Ray& ray, Color beta, float pdf_dir, RandomNumbers& rng,
                 int max_vertices, int roulette_after, Transport transport,
                 std::vector<Vertex>& path) {
    walk(b, ray, beta, pdf_dir, rng, max_vertices, roulette_after, transport, path,
         [&](const Vertex& v) { return v.bsdf->sample(v.si.wo, rng.uniform2(), transport); });
}

}  // namespace

void camera_subpath(const Bidir& b, const Ray& ray, RandomNumbers& rng, int max_vertices,
                    int roulette_after, std::vector<Vertex>& path) {
    path.clear();
    Vertex camera;
    camera.type = VertexType::Camera;
    camera.p = ray.origin;
    camera.beta = Color(1.0f);  // W / p = 1: a pixel's sample is the radiance it sees
    path.push_back(camera);
    random_walk(b, ray, Color(1.0f), b.camera.importance(ray.dir), rng, max_vertices,
                roulette_after, Transport::Radiance, path);
}

void light_subpath(const Bidir& b, RandomNumbers& rng, int max_vertices, int roulette_after,
                   std::vector<Vertex>& path) {
    path.clear();
    const float u_choose = rng.uniform();
    const Vec2 u_point = rng.uniform2();
    const Vec2 u_dir = rng.uniform2();
    const std::optional<EmissionSample> e = b.lights.sample_emission(u_choose, u_point, u_dir);
    if (!e || max_vertices < 1) return;
    Vertex light;
    light.type = VertexType::Light;
    light.p = e->directional ? -e->normal : e->point;
    light.n = e->is_delta() ? Vec3(0.0f) : e->normal;
    light.point_light = e->is_delta() && !e->directional;
    light.directional = e->directional;
    light.light_index = e->light_index;
    light.emitter = e->emitter;
    light.si.p_error = e->error;
    light.pdf_fwd = e->pdf_area;
    // y_0's beta: L_e / p_A(y_0) (a spot's: its axis intensity, as its cone's falloff depends on
    // where the light leaves to: camera_sees applies it); leaving it, times cos(theta) / p(w):
    // the light-side beta.
    const Color leaving = e->radiance / e->pdf_area;
    light.beta = light.point_light
                     ? b.scene.point_lights()[light.light_index].intensity / e->pdf_area
                     : leaving;
    path.push_back(light);
    const float cos_q = light.delta_light() ? 1.0f : std::fabs(glm::dot(e->normal, e->ray.dir));
    random_walk(b, e->ray, leaving * (cos_q / e->pdf_dir), e->pdf_dir, rng, max_vertices,
                roulette_after, Transport::Importance, path);
    if (path.size() >= 2) path[0].pdf_light_sample = light_sample_density(b, path[0], path[1]);
}

namespace {

// The direction a given path takes at v towards `next` (a point, or the sky's direction), as if
// the BSDF had sampled it: its density (a delta choice's, 1), and f = pdf / |cos|, so that the
// camera side's throughput stays 1 (the weights read densities only; the light side's takes the
// real f cos, and ends where it is 0).
std::optional<BsdfSample> towards(const Vertex& v, const Vertex& next) {
    const Vec3 wi = direction(v, next);
    if (v.bsdf->is_delta()) return BsdfSample{wi, Color(1.0f), 1.0f, true};
    const float pdf = v.bsdf->pdf(v.si.wo, wi);
    if (!(pdf > 0.0f)) return std::nullopt;
    return BsdfSample{wi, Color(pdf / std::max(v.bsdf->abs_cos(wi), 1e-6f)), pdf, false};
}

// Whether a vertex the walk made at a lies on the given point c (to rounding).
bool lies_on(const Vec3& a, const Vec3& c) {
    return glm::length(a - c) <= 1e-4f * (1.0f + glm::length(c));
}

// The k-th vertex after the camera's on the given path, in the camera subpath's order: x_{n-2},
// x_{n-3}, ..., x_1 (the points, last first), then the light.
Vertex camera_target(const Vertex& light, std::span<const Vec3> points, size_t k) {
    const size_t m = points.size();
    Vertex v = light;
    if (k < m) {
        v = Vertex{};
        v.p = points[m - 1 - k];
    }
    return v;
}

// The camera subpath: from the pinhole to x_{n-2}, x_{n-3}, ..., x_1, then the light. Returns why
// the given path cannot be followed ("" when it was).
std::string camera_subpath_along(const Bidir& b, const Vertex& light, std::span<const Vec3> points,
                                 std::vector<Vertex>& path) {
    Vertex camera;
    camera.type = VertexType::Camera;
    camera.p = b.camera.position();
    camera.beta = Color(1.0f);
    path.push_back(camera);
    const size_t m = points.size();
    const Vec3 first = direction(camera, camera_target(light, points, 0));
    const size_t camera_vertices = m + (light.delta_light() ? 1 : 2);
    size_t aimed = 0;
    Rng unused(0);
    walk(b, Ray{camera.p, first}, Color(1.0f), b.camera.importance(first), unused,
         static_cast<int>(camera_vertices), -1, Transport::Radiance, path,
         [&](const Vertex& v) -> std::optional<BsdfSample> {
             if (++aimed >= camera_vertices - 1) return std::nullopt;
             return towards(v, camera_target(light, points, aimed));
         });
    if (path.size() != camera_vertices)
        return "the camera subpath ends after " + std::to_string(path.size()) + " of its " +
               std::to_string(camera_vertices) + " vertices";
    for (size_t k = 0; k < m; ++k)
        if (!lies_on(path[1 + k].p, camera_target(light, points, k).p))
            return "the camera subpath's vertex " + std::to_string(1 + k) +
                   " misses its point (blocked)";
    if (!light.delta_light()) {  // the camera subpath ends on the light
        const Vertex& end = path.back();
        if (light.infinite ? !end.infinite
                           : end.primitive() != light.emitter || !lies_on(end.p, light.p))
            return "the camera subpath does not end on the light";
    }
    return "";
}

// The point light (an index into scene.point_lights()) at a given light vertex's position, or
// the directional light of its direction: UINT32_MAX if none.
uint32_t point_light_at(const Bidir& b, const Vertex& v) {
    const std::vector<PointLight>& lights = b.scene.point_lights();
    for (uint32_t i = 0; i < lights.size(); ++i)
        if (lights[i].position == v.p) return i;
    return UINT32_MAX;
}

uint32_t directional_light_at(const Bidir& b, const Vertex& v) {
    const std::vector<DirectionalLight>& lights = b.scene.directional_lights();
    for (uint32_t i = 0; i < lights.size(); ++i)
        if (glm::dot(-lights[i].direction, v.p) > 1.0f - 1e-6f) return i;
    return UINT32_MAX;
}

// The densities with which a light subpath starts as the given one does: y_0's own, the light's
// choice and its point's (set in y0.pdf_fwd), and, returned, that of its direction w towards x_1
// per steradian (uniform over the sphere for a point light, in its cone for a spot, the
// emission's for an area light; per m^2 across the beam for a directional light; 0 where it
// sends no light that way).
float light_start_densities(const Bidir& b, Vertex& y0, const Vec3& w) {
    LightSampler::EmissionPdf pdf;
    if (y0.point_light) y0.light_index = point_light_at(b, y0);
    if (y0.directional) y0.light_index = directional_light_at(b, y0);
    if (y0.point_light) pdf = b.lights.point_emission_pdf(y0.light_index, w);
    if (y0.directional) pdf = b.lights.directional_emission_pdf(y0.light_index);
    if (y0.delta_light()) {
        y0.pdf_fwd = pdf.area;
        return pdf.dir;
    }
    y0.pdf_fwd = light_origin_density(b, y0);
    return y0.emitter ? b.lights.emission_pdf(*y0.emitter, y0.n, w).dir : 0.0f;
}

// The light subpath: from the light to x_1, ..., x_{n-2}, through the same points (towards the
// camera, if there are none). Returns why the given path cannot be followed ("" when it was).
std::string light_subpath_along(const Bidir& b, const Vertex& light, std::span<const Vec3> points,
                                const Vertex& camera, std::vector<Vertex>& path) {
    const size_t m = points.size();
    Vertex y0 = light;
    y0.type = VertexType::Light;
    y0.beta = Color(1.0f);
    const Vec3 w = direction(y0, m > 0 ? camera_target(light, points, m - 1) : camera);
    const float pdf_dir = light_start_densities(b, y0, w);
    if (!(pdf_dir > 0.0f)) return "the light does not send light towards x_1";
    path.push_back(y0);
    if (m == 0) return "";  // a light seen directly: the light subpath is y_0 alone
    size_t next = 0;
    Rng unused(0);
    // A directional light's ray starts on its disk (LightSampler::beam_origin).
    const Ray first = y0.directional ? Ray{b.lights.beam_origin(w, points[0]), w, kInfinity}
                                     : spawn_ray(y0.surface_point(), w);
    walk(b, first, Color(1.0f), pdf_dir, unused, static_cast<int>(m + 1), -1, Transport::Importance,
         path, [&](const Vertex& v) -> std::optional<BsdfSample> {
             if (++next >= m) return std::nullopt;
             return towards(v, camera_target(light, points, m - 1 - next));
         });
    if (path.size() != m + 1)
        return "the light subpath ends after " + std::to_string(path.size()) + " of its " +
               std::to_string(m + 1) + " vertices";
    for (size_t i = 1; i <= m; ++i)
        if (!lies_on(path[i].p, points[i - 1]))
            return "the light subpath's vertex " + std::to_string(i) +
                   " misses its point (blocked)";
    path[0].pdf_light_sample = light_sample_density(b, path[0], path[1]);
    return "";
}

}  // namespace

std::optional<GivenSubpaths> subpaths_along(const Bidir& b, const Vertex& light,
                                            std::span<const Vec3> points, std::string* why) {
    auto fail = [&](const std::string& reason) -> std::optional<GivenSubpaths> {
        if (why) *why = reason;
        return std::nullopt;
    };
    GivenSubpaths out;
    const std::string camera_failed = camera_subpath_along(b, light, points, out.camera);
    if (!camera_failed.empty()) return fail(camera_failed);
    if (light.infinite) return out;  // the sky starts no light subpath
    const std::string light_failed =
        light_subpath_along(b, light, points, out.camera[0], out.light);
    if (!light_failed.empty()) return fail(light_failed);
    return out;
}

}  // namespace lessons
