// Error metrics of an image against a reference (see metrics.h).
#include "render/metrics.h"

#include <cmath>

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

}  // namespace lessons
