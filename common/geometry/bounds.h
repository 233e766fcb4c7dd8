// Axis-aligned bounding boxes, and the slab test used by the BVH.
#pragma once

#include <glm/common.hpp>

#include "geometry/math.h"

namespace lessons {

struct Bounds3 {
    Vec3 min{kInfinity};
    Vec3 max{-kInfinity};

    void expand(const Vec3& p) {
        min = glm::min(min, p);
        max = glm::max(max, p);
    }
    void expand(const Bounds3& b) {
        min = glm::min(min, b.min);
        max = glm::max(max, b.max);
    }
    bool empty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
    Vec3 centroid() const { return 0.5f * (min + max); }
    Vec3 extent() const { return max - min; }
    float surface_area() const {
        if (empty()) return 0.0f;
        const Vec3 e = extent();
        return 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
    }
    int longest_axis() const {
        const Vec3 e = extent();
        return (e.x >= e.y && e.x >= e.z) ? 0 : (e.y >= e.z ? 1 : 2);
    }
};

inline Bounds3 merge(Bounds3 a, const Bounds3& b) {
    a.expand(b);
    return a;
}

}  // namespace lessons
