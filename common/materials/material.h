// Materials: the physical parameters a scene gives a surface. Each lesson maps them onto its
// own illumination model (and says what it approximates or ignores); nothing here is a model.
#pragma once

#include <cmath>
#include <string>

#include "geometry/math.h"

namespace lessons {

enum class MaterialType {
    Diffuse,    // Lambertian: albedo
    Glossy,     // albedo (diffuse base) + a Blinn-Phong glossy lobe: specular and roughness
    Conductor,  // rough metal (GGX microfacets): specular = reflectance at normal incidence
    Mirror,     // perfect specular reflection: reflectance
    Glass,      // smooth dielectric: index of refraction
};

inline const char* material_type_name(MaterialType t) {
    switch (t) {
        case MaterialType::Diffuse: return "diffuse";
        case MaterialType::Glossy: return "glossy";
        case MaterialType::Conductor: return "conductor";
        case MaterialType::Mirror: return "mirror";
        case MaterialType::Glass: return "glass";
    }
    return "?";
}

// A reflectance that is either constant or a checkerboard over the surface's (u, v) in [0,1]^2.
struct ColorTexture {
    Color value{0.0f};  // constant value, or the colour of the "even" checker cells
    bool checker = false;
    Color odd{0.0f};   // colour of the "odd" checker cells
    Vec2 cells{1.0f};  // number of cells along u and v

    Color eval(const Vec2& uv) const {
        if (!checker) return value;
        // Cell (i, j) is odd when i + j is; fmod keeps this defined for any finite uv.
        const float i = std::floor(uv.x * cells.x), j = std::floor(uv.y * cells.y);
        return std::fabs(std::fmod(i + j, 2.0f)) == 1.0f ? odd : value;
    }
    // The mean over the surface: what a model that cannot see the pattern would use.
    Color average() const { return checker ? 0.5f * (value + odd) : value; }
};

struct Material {
    std::string name;
    MaterialType type = MaterialType::Diffuse;
    ColorTexture albedo;        // diffuse reflectance in [0, 1] (Diffuse, Glossy)
    Color specular{1.0f};       // lobe reflectance at normal incidence (Glossy, Conductor)
    float roughness = 0.5f;     // microfacet roughness alpha in (0, 1] (Glossy, Conductor)
    Color reflectance{1.0f};    // mirror reflectance (Mirror)
    float ior = 1.5f;           // index of refraction, inside over outside (Glass)
    Color transmittance{1.0f};  // fraction of the light crossing the surface that is kept (Glass)
    Color emission{0.0f};       // emitted radiance, W / (sr m^2)
    bool two_sided = false;     // emits from both sides (else only along the geometric normal)

    bool is_emissive() const { return !is_black(emission); }
};

}  // namespace lessons
