// EXR files written at test time through OpenEXR's own API, in every compression, pixel type and
// layout (scanlines, tiles, the first part of two), for the reader's tests (test_image.cpp).
#pragma once

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfMultiPartOutputFile.h>
#include <ImfOutputFile.h>
#include <ImfOutputPart.h>
#include <ImfPartType.h>
#include <ImfTiledOutputFile.h>
#include <half.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace exr_test {

enum class Layout { Scanline, Tiled, MultiPart };

inline const char* layout_name(Layout l) {
    return l == Layout::Scanline ? "scanline" : l == Layout::Tiled ? "tiled" : "multi-part";
}
inline const char* type_name(Imf::PixelType t) {
    return t == Imf::HALF ? "half" : t == Imf::FLOAT ? "float" : "uint";
}

// The value written to channel c of pixel (x, y) (data window coordinates from 0): a smooth
// HDR gradient (0.05 to about 1.1, 1.85 stops across, 1.6 down, half a stop between channels),
// held exactly by the type: rounded to half for half (and for float with `in_half`), an integer
// for uint.
inline float written_value(int x, int y, int c, Imf::PixelType type, bool in_half = false) {
    if (type == Imf::UINT) return static_cast<float>((x + 1000 * y) * 4 + c);
    const float v = 0.05f * std::exp2(0.05f * x + 0.08f * y + 0.5f * c);
    return type == Imf::HALF || in_half ? static_cast<float>(half(v)) : v;
}

struct Spec {
    Imf::Compression compression = Imf::ZIP_COMPRESSION;
    Imf::PixelType type = Imf::FLOAT;
    Layout layout = Layout::Scanline;
    std::vector<std::string> channels{"R", "G", "B"};
    int width = 37, height = 21;
    int x0 = -3, y0 = 5;  // the data window's origin
    bool values_in_half = false;  // float values rounded to half (the same texels in both)
};

// Writes `spec` to `path` with the values of written_value (channel k of `channels` is c = k,
// so "A" and "Y" get their own values); a multi-part file's second part is another image (a
// 5 x 3 Z channel of 7s) that the reader must leave alone.
inline void write(const std::string& path, const Spec& spec) {
    const Imath::Box2i window(Imath::V2i(spec.x0, spec.y0),
                              Imath::V2i(spec.x0 + spec.width - 1, spec.y0 + spec.height - 1));
    Imf::Header header(window, window);
    header.compression() = spec.compression;
    const size_t n = static_cast<size_t>(spec.width) * spec.height;
    const size_t size = spec.type == Imf::HALF ? 2 : 4;
    std::vector<std::vector<char>> planes;
    Imf::FrameBuffer frame;
    for (size_t k = 0; k < spec.channels.size(); ++k) {
        header.channels().insert(spec.channels[k], Imf::Channel(spec.type));
        std::vector<char> plane(n * size);
        for (int y = 0; y < spec.height; ++y)
            for (int x = 0; x < spec.width; ++x) {
                const float v =
                    written_value(x, y, static_cast<int>(k), spec.type, spec.values_in_half);
                char* at = plane.data() + (static_cast<size_t>(y) * spec.width + x) * size;
                if (spec.type == Imf::HALF) {
                    const half h(v);
                    std::memcpy(at, &h, 2);
                } else if (spec.type == Imf::FLOAT) {
                    std::memcpy(at, &v, 4);
                } else {
                    const auto u = static_cast<uint32_t>(v);
                    std::memcpy(at, &u, 4);
                }
            }
        planes.push_back(std::move(plane));
        frame.insert(spec.channels[k],
                     Imf::Slice::Make(spec.type, planes.back().data(), window, size));
    }
    if (spec.layout == Layout::Scanline) {
        Imf::OutputFile file(path.c_str(), header);
        file.setFrameBuffer(frame);
        file.writePixels(spec.height);
    } else if (spec.layout == Layout::Tiled) {
        header.setTileDescription(Imf::TileDescription(8, 8, Imf::ONE_LEVEL));
        Imf::TiledOutputFile file(path.c_str(), header);
        file.setFrameBuffer(frame);
        file.writeTiles(0, file.numXTiles() - 1, 0, file.numYTiles() - 1);
    } else {
        header.setName("beauty");
        header.setType(Imf::SCANLINEIMAGE);
        // (parts share their display window: OpenEXR refuses a file whose parts differ there)
        Imf::Header other(window, Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(4, 2)));
        other.setName("depth");
        other.setType(Imf::SCANLINEIMAGE);
        other.channels().insert("Z", Imf::Channel(Imf::FLOAT));
        const std::vector<Imf::Header> headers{header, other};
        Imf::MultiPartOutputFile file(path.c_str(), headers.data(), 2);
        Imf::OutputPart first(file, 0);
        first.setFrameBuffer(frame);
        first.writePixels(spec.height);
        std::vector<float> depth(15, 7.0f);
        Imf::FrameBuffer depth_frame;
        depth_frame.insert("Z", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(depth.data()), 4,
                                           4 * 5));
        Imf::OutputPart second(file, 1);
        second.setFrameBuffer(depth_frame);
        second.writePixels(3);
    }
}

}  // namespace exr_test
