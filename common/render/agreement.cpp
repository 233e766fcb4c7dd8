// Whether two renders estimate the same image within their noise (see agreement.h).
#include "render/agreement.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "io/input_error.h"

namespace lessons {

namespace {

// One block and channel of the test: the two block means and the variance of their
// difference, V_image + V_reference (with the floor (4) on the image's per pixel).
struct BlockTerm {
    double mean_image = 0.0, mean_reference = 0.0, var = 0.0;
};

// The block of pixels [bx, x1) x [by, y1), channel c: (1/n) sum m, (1/n^2) sum v.
BlockTerm block_term(const Image& image, const Image& variance, const Image& reference,
                     const Image& reference_variance, double floor_scale, int bx, int by, int x1,
                     int y1, int c) {
    const double n = static_cast<double>(x1 - bx) * (y1 - by);
    BlockTerm t;
    for (int y = by; y < y1; ++y)
        for (int x = bx; x < x1; ++x) {
            const size_t i = static_cast<size_t>(y) * image.width + x;
            t.mean_image += image.pixels[i][c];
            t.mean_reference += reference.pixels[i][c];
            const double v_reference = reference_variance.pixels[i][c];
            t.var +=
                std::max(double(variance.pixels[i][c]), v_reference * floor_scale) + v_reference;
        }
    t.mean_image /= n;
    t.mean_reference /= n;
    t.var /= n * n;
    return t;
}

}  // namespace

Agreement agreement(const Image& image, const Image& variance, const Image& reference,
                    const Image& reference_variance, int block, const std::string& what,
                    int image_spp, int reference_spp) {
    // (4): the reference's variance of one sample, over the image's sample count.
    const double floor_scale =
        image_spp > 0 && reference_spp > 0 ? double(reference_spp) / image_spp : 0.0;
    if (block < 1) throw std::invalid_argument("agreement: block must be at least 1");
    for (const Image* other : {&variance, &reference, &reference_variance})
        if (other->width != image.width || other->height != image.height)
            throw InputError(
                what, 0, "",
                "size " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                    " does not match the reference's and the variances' (" +
                    std::to_string(other->width) + "x" + std::to_string(other->height) + ")");
    Agreement a;
    a.block = block;
    for (int by = 0; by < image.height; by += block)
        for (int bx = 0; bx < image.width; bx += block) {
            const int x1 = std::min(bx + block, image.width),
                      y1 = std::min(by + block, image.height);
            for (int c = 0; c < 3; ++c) {
                // Block means and the variances of those means.
                const auto [mean_image, mean_reference, var] = block_term(
                    image, variance, reference, reference_variance, floor_scale, bx, by, x1, y1, c);
                const double d = mean_image - mean_reference;
                if (!(var > 0.0)) {
                    // No noise on either side: equal to float rounding (a few ulps of a float
                    // summed over the block), or a mismatch no noise explains.
                    ++a.exact_terms;
                    const double scale = std::max(std::fabs(mean_image), std::fabs(mean_reference));
                    if (!(std::fabs(d) <= 1e-5 * scale)) ++a.exact_mismatches;
                    continue;
                }
                const double z = d / std::sqrt(var);  // (1)
                ++a.terms;
                a.chi2 += z * z;  // (2)
                if (std::fabs(z) > 3.0) ++a.beyond_3;
                if (std::fabs(z) > std::fabs(a.worst_z)) {
                    a.worst_z = z;
                    a.worst_x = bx;
                    a.worst_y = by;
                    a.worst_channel = c;
                }
            }
        }
    if (a.terms > 0) {
        // Wilson-Hilferty, (3).
        const double k = a.terms, s2 = 2.0 / (9.0 * k);
        a.chi2_z = (std::cbrt(a.chi2 / k) - (1.0 - s2)) / std::sqrt(s2);
    }
    return a;
}

}  // namespace lessons
