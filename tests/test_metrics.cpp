// Error metrics against hand-computed values.
#include <gtest/gtest.h>

#include "io/input_error.h"
#include "render/metrics.h"

using namespace lessons;

TEST(Metrics, HandComputedValues) {
    Image reference(2, 1), image(2, 1);
    reference.pixels = {Color(1.0f, 0.0f, 0.5f), Color(0.0f)};
    image.pixels = {Color(1.5f, 0.0f, 0.5f), Color(0.0f, -1.0f, 0.0f)};
    const ErrorMetrics m = compare_images(image, reference);
    // d = (0.5, 0, 0, 0, -1, 0) over 6 channels.
    EXPECT_DOUBLE_EQ(m.mse, (0.25 + 1.0) / 6.0);
    EXPECT_DOUBLE_EQ(m.rmse, std::sqrt((0.25 + 1.0) / 6.0));
    EXPECT_DOUBLE_EQ(m.mae, 1.5 / 6.0);
    // relmse: 0.25 / (1 + 0.01) + 1 / (0 + 0.01), over 6.
    EXPECT_NEAR(m.relmse, (0.25 / 1.01 + 1.0 / 0.01) / 6.0, 1e-12);
}

TEST(Metrics, AReferenceAgainstItselfIsZeroAndSizesMustMatch) {
    Image a(3, 2);
    for (size_t i = 0; i < a.pixels.size(); ++i) a.pixels[i] = Color(0.1f * i, 2.0f, 1e4f);
    const ErrorMetrics m = compare_images(a, a);
    EXPECT_EQ(m.mse, 0.0);
    EXPECT_EQ(m.relmse, 0.0);
    EXPECT_EQ(m.mae, 0.0);
    EXPECT_THROW(compare_images(a, Image(2, 3), "x.exr"), InputError);
}
