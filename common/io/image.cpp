// Image output through stb_image_write (sRGB PNG); input from PNG and JPEG (stb_image), and by
// extension from EXR (image_exr.cpp, through OpenEXR) and Radiance .hdr (image_hdr.cpp).
#include "io/image.h"

#include <stb_image.h>
#include <stb_image_write.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace lessons {

float srgb_encode(float linear) {
    if (linear <= 0.0031308f) return 12.92f * linear;
    return 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

void rename_into_place(const std::string& tmp, const std::string& path) {
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        std::remove(tmp.c_str());
        throw std::runtime_error(path + ": cannot write (rename from temporary failed)");
    }
}

std::vector<uint8_t> display_bytes(const Image& image, float exposure_stops) {
    const float scale = std::exp2(exposure_stops);
    std::vector<uint8_t> bytes(static_cast<size_t>(image.width) * image.height * 3);
    for (size_t i = 0; i < image.pixels.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            float v = image.pixels[i][c] * scale;
            v = std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : (v > 0.0f ? 1.0f : 0.0f);
            bytes[3 * i + c] = static_cast<uint8_t>(std::lround(255.0f * srgb_encode(v)));
        }
    }
    return bytes;
}

void write_png(const Image& image, const std::string& path, float exposure_stops) {
    write_png_bytes(path, image.width, image.height, display_bytes(image, exposure_stops));
}

std::string encode_png(int width, int height, const std::vector<uint8_t>& rgb) {
    std::string png;
    auto append = [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<const char*>(data), size);
    };
    if (!stbi_write_png_to_func(append, &png, width, height, 3, rgb.data(), width * 3))
        throw std::runtime_error("cannot encode PNG");
    return png;
}

float srgb_decode(float v) {
    if (v <= 0.04045f) return v / 12.92f;
    return std::pow((v + 0.055f) / 1.055f, 2.4f);
}

void write_png_bytes(const std::string& path, int width, int height,
                     const std::vector<uint8_t>& rgb) {
    write_atomically(path, [&](const std::string& tmp) {
        if (!stbi_write_png(tmp.c_str(), width, height, 3, rgb.data(), width * 3)) {
            std::remove(tmp.c_str());
            throw std::runtime_error(path + ": cannot write PNG");
        }
    });
}

Image read_linear_image(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    return ext == ".hdr" ? read_hdr(path) : read_exr(path);
}

Image read_image(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    if (ext != ".png" && ext != ".jpg" && ext != ".jpeg") return read_linear_image(path);
    // 8- or 16-bit sRGB-encoded: decoded to linear by the standard curve.
    int w = 0, h = 0, channels = 0;
    const bool sixteen = stbi_is_16_bit(path.c_str());
    void* data = sixteen ? static_cast<void*>(stbi_load_16(path.c_str(), &w, &h, &channels, 3))
                         : static_cast<void*>(stbi_load(path.c_str(), &w, &h, &channels, 3));
    if (!data) {
        const char* why = stbi_failure_reason();
        throw std::runtime_error(path + ": cannot read the image" +
                                 (why ? std::string(": ") + why : ""));
    }
    Image image(w, h);
    for (size_t i = 0; i < image.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c)
            image.pixels[i][c] =
                sixteen ? srgb_decode(static_cast<const uint16_t*>(data)[3 * i + c] / 65535.0f)
                        : srgb_decode(static_cast<const uint8_t*>(data)[3 * i + c] / 255.0f);
    stbi_image_free(data);
    return image;
}

}  // namespace lessons
