// make_scene_maps: writes the images scenes/sky_map.toml uses, so that the files in the repository
// are made by code anyone can read and run:
//   build/bin/make_scene_maps scenes/maps
// sky.exr, a small latitude-longitude sky (docs/scene-format.md, "[background]"), and tiles.png,
// an 8-bit sRGB texture of terracotta tiles with pale grout.
// Rows run from the zenith (top) to the nadir (bottom), columns around the vertical axis (the
// environment map's convention, scene/environment.h). Above the horizon, a blue sky brightening
// to white at the horizon; below it, a dim brown ground; and one texel of sun, 35 degrees above
// the horizon, bright enough to cast shadows.
#include <CLI/CLI.hpp>
#include <cmath>
#include <iostream>
#include <vector>

#include "io/image.h"

int main(int argc, char** argv) {
    CLI::App app("Write the images of scenes/sky_map.toml: sky.exr and tiles.png", "make_scene_maps");
    std::string folder;
    int width = 64;
    app.add_option("folder", folder, "Where to write them")->required();
    app.add_option("--width", width, "Sky texels around (the height is half)")
        ->check(CLI::Range(4, 8192));
    CLI11_PARSE(app, argc, argv);
    const int height = width / 2;
    lessons::Image sky(width, height);
    const double pi = 3.14159265358979323846;
    for (int j = 0; j < height; ++j)
        for (int i = 0; i < width; ++i) {
            const double theta = pi * (j + 0.5) / height;  // from the zenith
            const double up = std::cos(theta);
            lessons::Color c;
            if (up > 0.0) {
                const float t = static_cast<float>(std::pow(1.0 - up, 3.0));  // 0 zenith, 1 horizon
                c = (1.0f - t) * lessons::Color(0.25f, 0.45f, 1.0f) + t * lessons::Color(1.0f);
            } else {
                c = lessons::Color(0.12f, 0.09f, 0.06f);
            }
            sky.at(i, j) = c;
        }
    // The sun: the texel 35 degrees above the horizon, a sixth of the way round.
    const int sun_row = static_cast<int>((90.0 - 35.0) / 180.0 * height);
    sky.at(width / 6, sun_row) = lessons::Color(400.0f, 380.0f, 330.0f);
    // Tiles: 4 x 4 terracotta tiles, each 14 texels with a 2-texel grout line, a little
    // variation from tile to tile.
    const int side = 64;
    std::vector<uint8_t> tiles(side * side * 3);
    for (int y = 0; y < side; ++y)
        for (int x = 0; x < side; ++x) {
            const bool grout = x % 16 < 2 || y % 16 < 2;
            const int shade = ((x / 16) * 7 + (y / 16) * 13) % 5;
            const uint8_t r = grout ? 215 : static_cast<uint8_t>(170 + 8 * shade);
            const uint8_t g = grout ? 205 : static_cast<uint8_t>(85 + 5 * shade);
            const uint8_t b = grout ? 190 : static_cast<uint8_t>(60 + 3 * shade);
            uint8_t* p = &tiles[(y * side + x) * 3];
            p[0] = r, p[1] = g, p[2] = b;
        }
    try {
        lessons::write_exr(sky, folder + "/sky.exr");
        lessons::write_png_bytes(folder + "/tiles.png", side, side, tiles);
    } catch (const std::exception& e) {
        std::cerr << "make_scene_maps: error: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
