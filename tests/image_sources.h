// Closed forms for the photon tests: a point light's irradiance on a plane (itself, or its image
// in a flat mirror), and that irradiance blurred by a photon kernel (kernel.h), the expectation
// of a density estimate at a fixed radius (docs/accuracy.md, "Density estimation").
#pragma once

#include <cmath>
#include <string>
#include <utility>

#include "06_photon_mapping/kernel.h"
#include "scene/scene.h"

namespace lessons::test {

// The irradiance a point source of intensity I (W/sr) gives a plane at height h below it, at
// lateral distance d from its foot: I cos / dist^2 = I h / (h^2 + d^2)^(3/2). A flat mirror of
// reflectance R at height H over the plane shows the source (at height h < H) as an image
// source of intensity R I at height 2H - h (where the reflected ray meets the mirror).
inline double point_irradiance(double I, double h, double d) {
    return I * h / std::pow(h * h + d * d, 1.5);
}

// The average of f over the disk of radius r about the plane point (x, z), weighted by the
// kernel: int K(|s|) f(x + s) d^2 s, which is the expectation of a density estimate of f at
// fixed radius r (K integrates to 1 over the disk). In polar coordinates (s, phi) about the
// point: Gauss-Legendre in s (8 nodes; f here is analytic, its nearest complex singularity at
// least the source's height h from the disk, so the error falls as (r / 2h)^16) and the
// trapezoidal rule in phi (32 nodes; exact up to terms of order (r / h)^32 for a periodic
// analytic integrand).
template <class F>
double kernel_average(Kernel kernel, double r, double x, double z, F&& f) {
    static constexpr double nodes[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                                        0.9602898564975363};
    static constexpr double weights[4] = {0.3626837833783620, 0.3137066458778873,
                                          0.2223810344533745, 0.1012285362903763};
    constexpr int angles = 32;
    double sum = 0.0;
    for (int i = 0; i < 8; ++i) {
        const double u = i < 4 ? -nodes[i] : nodes[i - 4];
        const double w = weights[i < 4 ? i : i - 4];
        const double s = 0.5 * r * (u + 1.0);
        double ring = 0.0;
        for (int k = 0; k < angles; ++k) {
            const double phi = 2.0 * kPi * k / angles;
            ring += f(x + s * std::cos(phi), z + s * std::sin(phi));
        }
        ring *= 2.0 * kPi / angles;
        sum += 0.5 * r * w * s *
               kernel_weight(kernel, static_cast<float>(s * s), static_cast<float>(r)) * ring;
    }
    return sum;
}

// A point light over a diffuse floor, under a flat mirror: the floor (y = 0, facing up, albedo
// rho) gets the light's irradiance and its image's (point_irradiance); a camera between the
// light and the mirror looks straight down at the light's foot. The floor and the mirror are
// 40 m squares, so both terms hold over everything the camera sees.
struct MirroredPointLight {
    double I = 1.0;    // W/sr
    double h = 0.5;    // the light's height
    double H = 0.75;   // the mirror's height
    double R = 0.8;    // its reflectance
    double rho = 0.5;  // the floor's albedo
    double image_height() const { return 2.0 * H - h; }
    // The floor's irradiance at lateral distance d from the foot: by the light itself, and by
    // its image in the mirror.
    double direct(double d) const { return point_irradiance(I, h, d); }
    double mirrored(double d) const { return point_irradiance(R * I, image_height(), d); }
};

// The scene: a size x size image, the camera at camera_height (below the mirror) looking
// straight down, its vertical field fov degrees.
inline Scene point_light_under_a_mirror(const MirroredPointLight& m, int size, float camera_height,
                                        float fov) {
    Scene scene;
    Material floor, mirror;
    floor.name = "floor";
    floor.albedo.value = Color(static_cast<float>(m.rho));
    mirror.name = "mirror";
    mirror.type = MaterialType::Mirror;
    mirror.reflectance = Color(static_cast<float>(m.R));
    const float H = static_cast<float>(m.H);
    scene.add_quad(Quad(Vec3(-20, 0, -20), Vec3(0, 0, 40), Vec3(40, 0, 0)),
                   scene.add_material(floor));  // normal +y
    scene.add_quad(Quad(Vec3(-20, H, -20), Vec3(40, 0, 0), Vec3(0, 0, 40)),
                   scene.add_material(mirror));  // normal -y
    scene.add_point_light({Vec3(0, static_cast<float>(m.h), 0), Color(static_cast<float>(m.I))});
    scene.width = scene.height = size;
    scene.camera = Camera(Vec3(0, camera_height, 0), Vec3(0), Vec3(0, 0, 1), fov, 1.0f);
    scene.commit();
    return scene;
}

// Where the ray meets the plane y = 0, as (x, z), in double.
inline std::pair<double, double> on_the_floor(const Ray& ray) {
    const double t = -static_cast<double>(ray.origin.y) / ray.dir.y;
    return {ray.origin.x + t * ray.dir.x, ray.origin.z + t * ray.dir.z};
}

}  // namespace lessons::test
