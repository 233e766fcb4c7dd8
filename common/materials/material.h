// Materials: the physical parameters a scene gives a surface. Each lesson maps them onto its
// own illumination model (and says what it approximates or ignores); nothing here is a model.
#pragma once

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "geometry/math.h"

namespace lessons {

enum class MaterialType {
    Diffuse,    // Lambertian: albedo
    Glossy,     // albedo (diffuse base) + a Blinn-Phong glossy lobe: specular and roughness
    Conductor,  // rough metal (GGX microfacets): specular = reflectance at normal incidence
    Mirror,     // perfect specular reflection: reflectance
    Glass,      // smooth dielectric: index of refraction
};

// What the rest of the suite asks of a material type, answered here once (a new type: its case
// here, its lobe in bsdf.h/.cpp, and the other places docs/architecture.md lists under "A
// material").
struct MaterialTypeFacts {
    const char* name;        // as scene files, reports and the scene export write it
    bool delta = false;      // scatters into single directions (a delta BSDF): only a sampled
                             // direction finds light through it, never a light sample
    bool transmits = false;  // light crosses it: its BSDF keeps the geometric orientation
    // The parameters of Material it uses (the others keep their defaults and mean nothing):
    bool albedo = false;       // albedo, a diffuse reflectance (what --albedo replaces)
    bool lobe = false;         // specular and roughness, a rough reflection lobe
    bool reflectance = false;  // reflectance (a mirror's)
    bool dielectric = false;   // ior and transmittance
};

inline constexpr MaterialTypeFacts facts_of(MaterialType t) {
    switch (t) {
        case MaterialType::Diffuse: return {.name = "diffuse", .albedo = true};
        case MaterialType::Glossy: return {.name = "glossy", .albedo = true, .lobe = true};
        case MaterialType::Conductor: return {.name = "conductor", .lobe = true};
        case MaterialType::Mirror: return {.name = "mirror", .delta = true, .reflectance = true};
        case MaterialType::Glass:
            return {.name = "glass", .delta = true, .transmits = true, .dielectric = true};
    }
    return {.name = "?"};
}

inline const char* material_type_name(MaterialType t) {
    return facts_of(t).name;
}

// An image of linear reflectances over (u, v) in [0, 1]^2 (io/texture.cpp reads it from PNG,
// JPEG or EXR). u runs left to right along a row, v bottom to top (the OBJ convention), so row 0
// of the image is v = 1. Texel (i, j) is centred at u = (i + 0.5) / width, v = 1 - (j + 0.5) /
// height; between centres, values are interpolated bilinearly.
struct ImageTexture {
    int width = 0, height = 0;
    std::vector<Color> texels;  // row-major, top row first
    Color mean{0.0f};           // over the texels
    std::string file;
    // The bilinear value at (u, v): beyond [0, 1], repeated (tiled) or clamped to the edge.
    Color lookup(Vec2 uv, bool repeat) const {
        if (!repeat) uv = glm::clamp(uv, Vec2(0.0f), Vec2(1.0f));  // NaN stays NaN: the mean below
        const float x = uv.x * width - 0.5f, y = (1.0f - uv.y) * height - 0.5f;
        const float fx = std::floor(x), fy = std::floor(y);
        const float tx = x - fx, ty = y - fy;
        auto texel = [&](float i, float j) {
            int a = static_cast<int>(i), b = static_cast<int>(j);
            if (repeat) {
                a %= width;
                b %= height;
                if (a < 0) a += width;
                if (b < 0) b += height;
            } else {
                a = a < 0 ? 0 : a >= width ? width - 1 : a;
                b = b < 0 ? 0 : b >= height ? height - 1 : b;
            }
            return texels[static_cast<size_t>(b) * width + a];
        };
        // a + t (b - a): equal neighbours give their value exactly (a flat texture is a colour).
        auto lerp = [](const Color& a, const Color& b, float t) { return a + t * (b - a); };
        // Far outside [0, 1] (|uv| ~ 1e7) the float coordinates lose their fraction: still a texel.
        if (!std::isfinite(x) || !std::isfinite(y) || std::fabs(x) > 1e8f || std::fabs(y) > 1e8f)
            return mean;
        return lerp(lerp(texel(fx, fy), texel(fx + 1, fy), tx),
                    lerp(texel(fx, fy + 1), texel(fx + 1, fy + 1), tx), ty);
    }
};

// A reflectance that is constant, a checkerboard over the surface's (u, v) in [0,1]^2, or an
// image texture.
struct ColorTexture {
    Color value{0.0f};  // constant value, or the colour of the "even" checker cells
    bool checker = false;
    Color odd{0.0f};   // colour of the "odd" checker cells
    Vec2 cells{1.0f};  // number of cells along u and v
    // An image: its file as the scene names it (resolved; read when the scene is built), the
    // image once read, the scale of (u, v) before the lookup, and repeat or clamp beyond [0, 1].
    std::string image_file;
    std::shared_ptr<const ImageTexture> image;
    Vec2 scale{1.0f};
    bool repeat = true;
    Color eval(const Vec2& uv) const {
        if (image) return image->lookup(uv * scale, repeat);
        if (!checker) return value;
        // Cell (i, j) is odd when i + j is; fmod keeps this defined for any finite uv.
        const float i = std::floor(uv.x * cells.x), j = std::floor(uv.y * cells.y);
        return std::fabs(std::fmod(i + j, 2.0f)) == 1.0f ? odd : value;
    }
    // The mean over the surface: what a model that cannot see the pattern would use.
    Color average() const { return image ? image->mean : checker ? 0.5f * (value + odd) : value; }
    // The largest value anywhere (for energy checks).
    Color maximum() const;
};

inline Color ColorTexture::maximum() const {
    if (image) {
        Color m(0.0f);
        for (const Color& c : image->texels) m = glm::max(m, c);
        return m;
    }
    return checker ? glm::max(value, odd) : value;
}

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
