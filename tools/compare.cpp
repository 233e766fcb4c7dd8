// compare: how far an image is from a reference.
//
//   build/bin/compare IMAGE REFERENCE [--second-half REFERENCE2] [--out PREFIX] [--scale MAX]
//
// Prints mse, rmse, relmse and mae (common/render/metrics.h) as one JSON line. With --second-half, the
// reference is the mean of two independent renders (halves) A and B, and its own noise is
// estimated and subtracted: the mean of two halves has per-pixel variance MSE(A, B) / 4, and
// an image independent of both has MSE(image, reference) = its true MSE + that variance. The
// line then adds reference_noise_mse, mse_corrected and rmse_corrected
// (docs/performance.md). With --out, writes
// PREFIX_error.png, the per-pixel error |image - reference| (RMS over the channels) in the
// viridis colour map, dark for 0 and yellow for MAX (default: the 99th percentile of the error),
// with the scale drawn beneath; and PREFIX_side_by_side.png: image | reference | error.
// Inputs are EXR (linear) or PNG (sRGB, decoded to linear). Exit 2 on unreadable files or
// different sizes.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "io/image.h"
#include "io/input_error.h"
#include "render/metrics.h"

using namespace lessons;

namespace {

// A 3 x 5 pixel font for the scale's numbers.
const char* glyph(char ch) {
    switch (ch) {
        case '0': return "111101101101111";
        case '1': return "010110010010111";
        case '2': return "111001111100111";
        case '3': return "111001111001111";
        case '4': return "101101111001001";
        case '5': return "111100111001111";
        case '6': return "111100111101111";
        case '7': return "111001001001001";
        case '8': return "111101111101111";
        case '9': return "111101111001111";
        case '.': return "000000000000010";
        case 'e': return "000111101110011";
        case '-': return "000000111000000";
        case '+': return "000010111010000";
        default: return "000000000000000";
    }
}

struct Canvas {
    int width, height;
    std::vector<uint8_t> rgb;
    Canvas(int w, int h) : width(w), height(h), rgb(static_cast<size_t>(w) * h * 3, 255) {}
    void set(int x, int y, const std::array<uint8_t, 3>& c) {
        if (x < 0 || y < 0 || x >= width || y >= height) return;
        for (int k = 0; k < 3; ++k) rgb[(static_cast<size_t>(y) * width + x) * 3 + k] = c[k];
    }
    void text(int x, int y, const std::string& s, int scale) {
        for (char ch : s) {
            const char* g = glyph(ch);
            for (int r = 0; r < 5; ++r)
                for (int c = 0; c < 3; ++c)
                    if (g[r * 3 + c] == '1')
                        for (int dy = 0; dy < scale; ++dy)
                            for (int dx = 0; dx < scale; ++dx)
                                set(x + c * scale + dx, y + r * scale + dy, {0, 0, 0});
            x += 4 * scale;
        }
    }
    void image(int x0, int y0, const Image& im) {  // linear radiance, clamped, sRGB
        for (int y = 0; y < im.height; ++y)
            for (int x = 0; x < im.width; ++x) {
                std::array<uint8_t, 3> c;
                for (int k = 0; k < 3; ++k) {
                    const float v = im.at(x, y)[k];
                    c[k] = static_cast<uint8_t>(std::lround(
                        255.0f * srgb_encode(std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 1.0f)));
                }
                set(x0 + x, y0 + y, c);
            }
    }
};

// A variance image must be the size of the image it belongs to.
void check_size(const Image& variance, const std::string& path, const Image& like) {
    if (variance.width != like.width || variance.height != like.height)
        throw std::runtime_error(path + ": not the size of the image");
}

std::string format_number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return buf;
}

// The command line.
struct Options {
    std::string image_path, reference_path, out;
    double scale = 0.0;
    std::string second_half;
    std::string variance_path, reference_variance_path;
    int blocks = 0;
    std::string image_second_half;
};

void declare_options(CLI::App& app, Options& o) {
    app.add_option("image", o.image_path, "The image to judge (EXR or PNG)")->required();
    app.add_option("reference", o.reference_path, "The reference (EXR or PNG)")->required();
    app.add_option("--second-half", o.second_half,
                   "A second, independent reference render: the reference becomes the mean of "
                   "the two, and its own noise is subtracted from the MSE");
    app.add_option("--variance", o.variance_path,
                   "The image's per-pixel variance of the mean (a lesson's --variance EXR): with "
                   "it, \"bias2\" estimates the MSE the image converges to, its squared bias: "
                   "mse minus the mean variance of the image and of the reference (renders of "
                   "--sampler independent: a stratified sampler's variance image is not its "
                   "error), with its standard error \"bias2_se\" (the pixels taken as "
                   "independent)");
    app.add_option("--reference-variance", o.reference_variance_path,
                   "The reference's per-pixel variance of the mean, for bias2");
    app.add_option("--blocks", o.blocks,
                   "Also compare the image's mean with the reference's, whole and in blocks of "
                   "this many pixels square: mean_ratio and the block ratios' range, and with "
                   "both second halves their standard errors")
        ->check(CLI::Range(1, 1 << 20));
    app.add_option("--image-second-half", o.image_second_half,
                   "A second, independent render of the image: with --blocks, the image is the "
                   "mean of the two, and the noise of its means is estimated from them");
    app.add_option("--out", o.out, "Write PREFIX_error.png and PREFIX_side_by_side.png");
    app.add_option("--scale", o.scale,
                   "Error mapped to the top of the colour map (default: 99th "
                   "percentile)")
        ->check(CLI::PositiveNumber);
}

// With --image-second-half, the image becomes the mean of its two halves.
void average_image_halves(const Options& o, Image& image, const Image& image_b) {
    if (o.image_second_half.empty()) return;
    if (image_b.width != image.width || image_b.height != image.height)
        throw InputError(o.image_second_half, 0, "", "not the image's size");
    for (size_t i = 0; i < image.pixels.size(); ++i)
        image.pixels[i] = 0.5f * (image.pixels[i] + image_b.pixels[i]);
}

// With --second-half, the reference becomes the mean of its two halves A and B; returns that
// mean's own noise, its per-pixel variance MSE(A, B) / 4 (0 without a second half).
double average_reference_halves(const Options& o, Image& reference, const Image& b) {
    if (o.second_half.empty()) return 0.0;
    const double reference_noise = compare_images(b, reference, o.second_half).mse / 4.0;
    for (size_t i = 0; i < reference.pixels.size(); ++i)
        reference.pixels[i] = 0.5f * (reference.pixels[i] + b.pixels[i]);
    return reference_noise;
}

// An image read by read_image, its notes (a multi-part EXR's other parts ignored) on stderr.
Image read_noted(const std::string& path) {
    Image image = read_image(path);
    for (const std::string& note : image.notes) std::fprintf(stderr, "note: %s\n", note.c_str());
    return image;
}

// With --variance: the error more samples cannot remove (converged_error, render/metrics.h).
void print_bias(const Options& o, const Image& image, const Image& reference) {
    const Image variance = read_noted(o.variance_path);
    check_size(variance, o.variance_path, image);
    Image reference_variance;
    if (!o.reference_variance_path.empty()) {
        reference_variance = read_noted(o.reference_variance_path);
        check_size(reference_variance, o.reference_variance_path, image);
    }
    const ConvergedError c = converged_error(
        image, reference, variance,
        o.reference_variance_path.empty() ? nullptr : &reference_variance);
    std::printf(", \"noise_mse\": %.9g, \"bias2\": %.9g, \"bias2_se\": %.3g", c.noise_mse,
                c.bias2, c.bias2_se);
}

// With --second-half: the MSE less the reference's own noise.
void print_corrected(const ErrorMetrics& m, double reference_noise) {
    const double corrected = m.mse - reference_noise;
    std::printf(
        ", \"reference_noise_mse\": %.9g, \"mse_corrected\": %.9g, "
        "\"rmse_corrected\": %.9g",
        reference_noise, corrected, std::sqrt(std::max(0.0, corrected)));
}

// With --blocks: the means compared, whole and block by block.
void print_means(const MeanComparison& c) {
    std::printf(
        ", \"block\": %d, \"blocks\": %d, \"blocks_compared\": %d, \"image_mean\": %.9g, "
        "\"reference_mean\": %.9g, \"mean_ratio\": %.9g, \"mean_ratio_noise\": %.3g, "
        "\"block_ratio_min\": %.9g, \"block_ratio_max\": %.9g, "
        "\"block_ratio_noise\": %.3g, \"worst_block\": [%d, %d], "
        "\"worst_block_ratio\": %.9g, \"worst_block_ratio_noise\": %.3g",
        c.block, c.blocks_x * c.blocks_y, c.blocks_compared, c.image_mean, c.reference_mean,
        c.mean_ratio, c.mean_ratio_noise, c.ratio_min, c.ratio_max, c.block_ratio_noise, c.worst_x,
        c.worst_y, c.worst_ratio, c.worst_ratio_noise);
}

// Reads the images, makes each the mean of its halves where two are given, and prints the metrics
// as one JSON line; `image` and `reference` are left as they were compared.
void print_metrics(const Options& o, Image& image, Image& reference) {
    image = read_noted(o.image_path);
    reference = read_noted(o.reference_path);
    Image image_b, reference_b;
    if (!o.image_second_half.empty()) image_b = read_noted(o.image_second_half);
    if (!o.second_half.empty()) reference_b = read_noted(o.second_half);
    // The block means see both halves themselves (their noise comes from the difference).
    std::optional<MeanComparison> means;
    if (o.blocks > 0)
        means = compare_means(image, reference, o.blocks,
                              o.image_second_half.empty() ? nullptr : &image_b,
                              o.second_half.empty() ? nullptr : &reference_b);
    average_image_halves(o, image, image_b);
    const double reference_noise = average_reference_halves(o, reference, reference_b);
    const ErrorMetrics m = compare_images(image, reference, o.image_path);
    std::printf("{\"mse\": %.9g, \"rmse\": %.9g, \"relmse\": %.9g, \"mae\": %.9g", m.mse, m.rmse,
                m.relmse, m.mae);
    if (!o.variance_path.empty()) print_bias(o, image, reference);
    if (!o.second_half.empty()) print_corrected(m, reference_noise);
    if (means) print_means(*means);
    std::printf("}\n");
}

constexpr int kBar = 14, kLabel = 16;  // the colour bar and its numbers beneath the image

// The per-pixel error of a w x h image in the viridis colour map, 0 to `scale`, with the scale
// drawn beneath.
Canvas error_canvas(const std::vector<float>& error, int w, int h, double scale) {
    Canvas error_png(w, h + kBar + kLabel);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            error_png.set(
                x, y, viridis(static_cast<float>(error[static_cast<size_t>(y) * w + x] / scale)));
    for (int x = 0; x < w; ++x)
        for (int y = h + 2; y < h + kBar; ++y)
            error_png.set(x, y, viridis(static_cast<float>(x) / (w - 1)));
    const std::string top = format_number(scale) + "+";
    error_png.text(2, h + kBar + 2, "0", 2);
    error_png.text(w - 8 * static_cast<int>(top.size()) - 2, h + kBar + 2, top, 2);
    return error_png;
}

// image | reference | error.
Canvas side_by_side(const Image& image, const Image& reference, const Canvas& error_png) {
    const int w = image.width, h = image.height;
    Canvas side(3 * w + 8, h + kBar + kLabel);
    side.image(0, 0, image);
    side.image(w + 4, 0, reference);
    for (int y = 0; y < error_png.height; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t i = (static_cast<size_t>(y) * w + x) * 3;
            side.set(2 * w + 8 + x, y,
                     {error_png.rgb[i], error_png.rgb[i + 1], error_png.rgb[i + 2]});
        }
    return side;
}

// With --out: PREFIX_error.png and PREFIX_side_by_side.png; the exit status.
int write_error_images(const Options& o, const Image& image, const Image& reference) {
    const std::vector<float> error = pixel_errors(image, reference);
    double scale = o.scale;
    if (scale <= 0.0) scale = error_map_scale(error);
    const Canvas error_png = error_canvas(error, image.width, image.height, scale);
    const Canvas side = side_by_side(image, reference, error_png);
    try {
        write_png_bytes(o.out + "_error.png", error_png.width, error_png.height, error_png.rgb);
        write_png_bytes(o.out + "_side_by_side.png", side.width, side.height, side.rgb);
    } catch (const std::exception& e) {
        std::cerr << "compare: error: " << e.what() << "\n";
        return 1;
    }
    std::fprintf(stderr, "compare: error scale 0 .. %g (RMS over channels, linear radiance)\n",
                 scale);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app("Compare an image with a reference: error metrics, error image, side by side",
                 "compare");
    Options o;
    declare_options(app, o);
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << "compare: error: command line: " << e.what() << " (see --help)\n";
        return 2;
    }
    Image image, reference;
    try {
        print_metrics(o, image, reference);
    } catch (const std::exception& e) {
        std::cerr << "compare: error: " << e.what() << "\n";
        return 2;
    }
    if (o.out.empty()) return 0;
    return write_error_images(o, image, reference);
}
