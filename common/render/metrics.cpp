// Error metrics of an image against a reference (see metrics.h).
#include "render/metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <limits>
#include <stdexcept>

#include "io/input_error.h"

namespace lessons {

ErrorMetrics compare_images(const Image& image, const Image& reference, const std::string& what) {
    if (image.width != reference.width || image.height != reference.height)
        throw InputError(what, 0, "",
                         "size " + std::to_string(image.width) + "x" +
                             std::to_string(image.height) + " does not match the reference's " +
                             std::to_string(reference.width) + "x" +
                             std::to_string(reference.height));
    double squared = 0.0, relative = 0.0, absolute = 0.0;
    for (size_t i = 0; i < image.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const double ref = reference.pixels[i][c];
            const double d = static_cast<double>(image.pixels[i][c]) - ref;
            squared += d * d;
            relative += d * d / (ref * ref + 0.01);
            absolute += std::fabs(d);
        }
    const double n = 3.0 * static_cast<double>(image.pixels.size());
    ErrorMetrics m;
    if (n == 0.0) return m;
    m.mse = squared / n;
    m.rmse = std::sqrt(m.mse);
    m.relmse = relative / n;
    m.mae = absolute / n;
    return m;
}

ConvergedError converged_error(const Image& image, const Image& reference, const Image& variance,
                               const Image* reference_variance) {
    for (const Image* other : {&reference, &variance, reference_variance})
        if (other && (other->width != image.width || other->height != image.height))
            throw std::invalid_argument("converged_error: the images differ in size");
    ConvergedError out;
    double sum = 0.0, sum2 = 0.0, noise = 0.0;
    const size_t n = image.pixels.size();
    for (size_t i = 0; i < n; ++i) {
        const Color d = image.pixels[i] - reference.pixels[i];
        Color v = variance.pixels[i];
        if (reference_variance) v += reference_variance->pixels[i];
        const double var = (double(v.x) + v.y + v.z) / 3.0;
        const double e = (double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z) / 3.0 - var;
        noise += var;
        sum += e;
        sum2 += e * e;
    }
    if (n == 0) return out;
    out.noise_mse = noise / static_cast<double>(n);
    out.bias2 = sum / static_cast<double>(n);
    const double spread =
        n > 1 ? std::max(0.0, (sum2 - sum * out.bias2) / static_cast<double>(n - 1)) : 0.0;
    out.bias2_se = std::sqrt(spread / static_cast<double>(n));
    return out;
}

namespace {

// Viridis (van der Walt and Smith, matplotlib): perceptually uniform and ordered, readable in
// grey and by colour-blind viewers. Sampled at 0, 0.1, ..., 1.
constexpr std::array<std::array<uint8_t, 3>, 11> kViridis = {{{0x44, 0x01, 0x54},
                                                              {0x48, 0x24, 0x75},
                                                              {0x41, 0x44, 0x87},
                                                              {0x35, 0x5F, 0x8D},
                                                              {0x2A, 0x78, 0x8E},
                                                              {0x21, 0x91, 0x8C},
                                                              {0x22, 0xA8, 0x84},
                                                              {0x44, 0xBF, 0x70},
                                                              {0x7A, 0xD1, 0x51},
                                                              {0xBD, 0xDF, 0x26},
                                                              {0xFD, 0xE7, 0x25}}};

}  // namespace

namespace {
// Sums of the three channels over square blocks, row-major.
std::vector<double> block_sums(const Image& im, int block, int bx, int by) {
    std::vector<double> sums(static_cast<size_t>(bx) * by, 0.0);
    for (int y = 0; y < im.height; ++y)
        for (int x = 0; x < im.width; ++x) {
            const Color& c = im.pixels[static_cast<size_t>(y) * im.width + x];
            sums[static_cast<size_t>(y / block) * bx + x / block] += double(c.r) + c.g + c.b;
        }
    return sums;
}

// Throws InputError unless every image given (the null ones are not) has image's size.
void check_same_size(const Image& image, std::initializer_list<const Image*> others) {
    for (const Image* other : others)
        if (other && (other->width != image.width || other->height != image.height))
            throw InputError("image", 0, "",
                             "sizes differ: " + std::to_string(image.width) + "x" +
                                 std::to_string(image.height) + " against " +
                                 std::to_string(other->width) + "x" +
                                 std::to_string(other->height));
}

// The block sums of a render (compare_means' blocks), or with its second half b, the mean of
// the two halves' sums.
std::vector<double> render_block_sums(const Image& a, const Image* b, const MeanComparison& r) {
    std::vector<double> s = block_sums(a, r.block, r.blocks_x, r.blocks_y);
    if (b) {
        const std::vector<double> t = block_sums(*b, r.block, r.blocks_x, r.blocks_y);
        for (size_t i = 0; i < s.size(); ++i) s[i] = 0.5 * (s[i] + t[i]);
    }
    return s;
}

// Each block's relative variance from a render's two halves a and b (none without b): the mean
// M = (A + B) / 2 of two independent halves has Var(M) = E[(A - B)^2] / 4, so (A - B)^2 /
// (A + B)^2 relative to M^2 (one degree of freedom per block). Sets var per block, and adds to
// d2 the sum of (A - B)^2 / 4 over every block.
void add_half_variances(const Image& a, const Image* b, const MeanComparison& r,
                        std::vector<double>& var, double& d2) {
    if (!b) return;
    const std::vector<double> sa = block_sums(a, r.block, r.blocks_x, r.blocks_y),
                              sb = block_sums(*b, r.block, r.blocks_x, r.blocks_y);
    for (size_t i = 0; i < sa.size(); ++i) {
        const double d = sa[i] - sb[i], m = sa[i] + sb[i];
        d2 += 0.25 * d * d;
        if (m > 0.0) var[i] = d * d / (m * m);
    }
}
}  // namespace

MeanComparison compare_means(const Image& image, const Image& reference, int block,
                             const Image* image_b, const Image* reference_b) {
    check_same_size(image, {&reference, image_b, reference_b});
    MeanComparison r;
    r.block = std::max(1, block);
    r.blocks_x = (image.width + r.block - 1) / r.block;
    r.blocks_y = (image.height + r.block - 1) / r.block;
    const std::vector<double> im = render_block_sums(image, image_b, r),
                              ref = render_block_sums(reference, reference_b, r);
    double total_im = 0.0, total_ref = 0.0;
    for (size_t i = 0; i < im.size(); ++i) total_im += im[i], total_ref += ref[i];
    const double pixels = 3.0 * image.width * image.height;
    r.image_mean = total_im / pixels;
    r.reference_mean = total_ref / pixels;
    r.mean_ratio = total_ref > 0.0 ? total_im / total_ref : 0.0;
    // Each block's relative variance from the halves (add_half_variances).
    std::vector<double> var_im(im.size(), 0.0), var_ref(im.size(), 0.0);
    double diff2_im = 0.0, diff2_ref = 0.0;  // sums of (A - B)^2 / 4 over every block
    add_half_variances(image, image_b, r, var_im, diff2_im);
    add_half_variances(reference, reference_b, r, var_ref, diff2_ref);
    const double floor = 1e-3 * total_ref / static_cast<double>(im.size());
    r.ratios.assign(im.size(), std::nan(""));
    r.ratio_min = std::numeric_limits<double>::infinity();
    r.ratio_max = -r.ratio_min;
    double pooled = 0.0;
    for (size_t i = 0; i < im.size(); ++i) {
        if (!(ref[i] > floor && ref[i] > 0.0)) continue;  // black in the reference: no ratio
        const double q = im[i] / ref[i];
        r.ratios[i] = q;
        ++r.blocks_compared;
        pooled += var_im[i] + var_ref[i];
        r.ratio_min = std::min(r.ratio_min, q);
        r.ratio_max = std::max(r.ratio_max, q);
        if (r.blocks_compared == 1 || std::fabs(q - 1.0) > std::fabs(r.worst_ratio - 1.0)) {
            r.worst_ratio = q;
            r.worst_ratio_noise = std::sqrt(var_im[i] + var_ref[i]);
            r.worst_x = static_cast<int>(i % r.blocks_x) * r.block;
            r.worst_y = static_cast<int>(i / r.blocks_x) * r.block;
        }
    }
    if (r.blocks_compared == 0) r.ratio_min = r.ratio_max = 0.0;
    if (r.blocks_compared > 0) r.block_ratio_noise = std::sqrt(pooled / r.blocks_compared);
    // The whole mean: the blocks' noise is independent, so Var(total) = sum of the blocks'.
    if ((image_b || reference_b) && total_im > 0.0 && total_ref > 0.0)
        r.mean_ratio_noise =
            std::sqrt(diff2_im / (total_im * total_im) + diff2_ref / (total_ref * total_ref));
    return r;
}

std::array<uint8_t, 3> viridis(float t) {
    t = std::isfinite(t) ? std::clamp(t, 0.0f, 1.0f) : 1.0f;
    const float x = t * 10.0f;
    const int i = std::min(9, static_cast<int>(x));
    const float f = x - i;
    std::array<uint8_t, 3> c;
    for (int k = 0; k < 3; ++k)
        c[k] = static_cast<uint8_t>(std::lround((1 - f) * kViridis[i][k] + f * kViridis[i + 1][k]));
    return c;
}

std::vector<float> pixel_errors(const Image& image, const Image& reference) {
    std::vector<float> error(image.pixels.size());
    for (size_t i = 0; i < error.size() && i < reference.pixels.size(); ++i) {
        const Color d = image.pixels[i] - reference.pixels[i];
        error[i] = std::sqrt(glm::dot(d, d) / 3.0f);
    }
    return error;
}

double error_map_scale(const std::vector<float>& errors) {
    std::vector<float> sorted(errors);
    std::sort(sorted.begin(), sorted.end());
    const double scale =
        sorted.empty() ? 1.0 : sorted[static_cast<size_t>(0.99 * (sorted.size() - 1))];
    return scale > 0.0 ? scale : 1.0;
}

std::vector<std::string> layer_shares(const Image& image, const std::vector<Image>& layers,
                                      const std::vector<std::string>& names) {
    std::vector<std::string> shares;
    double total_luminance = 0.0;
    for (const Color& c : image.pixels) total_luminance += luminance(c);
    for (size_t k = 0; k < layers.size(); ++k) {
        double layer_luminance = 0.0;
        for (const Color& c : layers[k].pixels) layer_luminance += luminance(c);
        const double share = total_luminance > 0.0 ? layer_luminance / total_luminance : 0.0;
        char line[160];
        std::snprintf(line, sizeof line, "%s: %.2f%% of the image's energy", names[k].c_str(),
                      100.0 * share);
        shares.push_back(line);
    }
    return shares;
}

}  // namespace lessons
