// Lesson 6, section 1: the photon map. A photon is a light-subpath vertex y_i (i >= 1) on a
// surface that scatters diffusely or glossily: where the light arrived, from which direction and
// with how much flux. The radiance estimate (density.h) sums the photons within a radius r of a
// camera-path vertex, so the map has one question to answer, fast: which photons lie within r
// of x?
//
// Why a hashed uniform grid and not a kd-tree (Jensen 2001's photon map):
//  - the radius is fixed for a whole iteration (progressive photon mapping shrinks it from one
//    iteration to the next, never within one), so the query is a fixed-radius range query, not
//    a k-nearest-neighbour search; a grid of cells of size 2r answers it by visiting 2 x 2 x 2
//    cells, with no tree descent and no stack;
//  - the photons are traced afresh every iteration, so the map is built every iteration: the
//    grid's build is a counting sort, O(N) in two passes, against the kd-tree's O(N log N);
//  - its memory is the photons and one offset per bucket, known in advance.
// Vertex connection and merging does the same (Georgiev, Krivanek, Davidovic and Slusallek,
// "Light Transport Simulation with Vertex Connection and Merging", SIGGRAPH Asia 2012, and its
// reference implementation SmallVCM, whose HashGrid this follows).
//
// The hash (Teschner, Heidelberger, Mueller, Pomeranets and Gross, "Optimized Spatial Hashing
// for Collision Detection of Deformable Objects", VMV 2003): integer cell coordinates (i, j, k)
// go to bucket (i 73856093 XOR j 19349663 XOR k 83492791) mod B (B a power of two). Cells that
// share a bucket only cost a few extra distance tests: a bucket is searched by distance, never
// trusted.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "geometry/bounds.h"
#include "geometry/math.h"

namespace lessons {

// One photon: light arriving at a surface point, as a light subpath brought it there.
struct Photon {
    Vec3 p{0.0f};         // where it landed (the vertex y_i)
    Vec3 wi{0.0f};        // unit direction it arrived from, pointing away from the surface (y_i's
                          // si.wo: towards y_{i-1})
    Color beta{0.0f};     // the light subpath's throughput at y_i (lesson 5's beta: L_e / p(y_0)
                          // times cos / p(w) leaving the light, times f cos / p at each bounce
                          // before y_i): flux carried per light subpath, W
    Vec3 n{0.0f};         // unit geometric normal at p (the shape's front side)
    uint32_t path = 0;    // which light subpath of its iteration (photons.h)
    uint32_t vertex = 0;  // which vertex i of that subpath (the light's path has i segments)
    // Vertex connection and merging: the light side of the merge's weight, computed once per
    // photon (weigh_photons, photon_mapping.h): the square roots of MergeLightSide's
    // per_reverse2 and own_join (merge_weights.h), so that a float holds their range.
    float merge_reverse_root = 0.0f, merge_own_root = 0.0f;
};

// A hashed uniform grid over photons for queries of one fixed radius r.
//
// Cell size 2r, and a query visits 2 x 2 x 2 cells: the ball of radius r about x is one cell
// wide, so along each axis it meets x's own cell and one neighbour, the one on the side of the
// cell's middle that x lies on. The alternative, cells of size r and 3 x 3 x 3 of them, tests
// fewer photons on a flat surface (a 3r x 3r square against 4r x 4r: 9 r^2 against 16 r^2 of
// surface) but looks up 27 buckets instead of 8, each a hash and likely a cache miss, which
// cost more than the extra distance tests when a good radius gathers a few tens of photons;
// SmallVCM makes the same choice. (The cells are 2r (1 + 2^-10) wide, so that a photon the
// float distance test accepts lies in a visited cell even after rounding.)
//
// Deterministic: the photons are counting-sorted by bucket, stably, in the order given (only the
// buckets are computed on several threads, each photon's alone), so the grid is the same bits
// for any number of threads; a query visits its buckets in a fixed order and each bucket's
// photons in that order.
class PhotonGrid {
public:
    PhotonGrid() = default;
    // The grid over `photons` for queries of radius `radius` (> 0, finite; else
    // std::invalid_argument). buckets: how many, rounded up to a power of two; 0 for the
    // smallest power of two at least the photon count (about one photon per bucket; tests pass
    // a few to force collisions).
    // Photons with a non-finite position are left out: no query can be within r of them.
    PhotonGrid(std::span<const Photon> photons, float radius, int threads = 0, size_t buckets = 0);

    float radius() const { return radius_; }
    size_t size() const { return photons_.size(); }
    // The photons in the grid's order (by bucket).
    std::span<const Photon> photons() const { return photons_; }
    // Memory held: the sorted photons and the buckets' offsets, in bytes (the arrays' sizes).
    size_t bytes() const {
        return photons_.size() * sizeof(Photon) + bucket_start_.size() * sizeof(uint32_t);
    }

    // Calls fn(photon) for every photon with |photon.p - x| < r (the distance in float, as
    // d = p - x; dot(d, d) < r * r), each once, in a fixed order.
    template <class Fn>
    void for_each_within(const Vec3& x, Fn&& fn) const {
        if (photons_.empty() || !is_finite(x)) return;
        for (int a = 0; a < 3; ++a)  // beyond 2r of the photons' box (r, and room for rounding)
            if (x[a] < bounds_.min[a] - 2.0f * radius_ || x[a] > bounds_.max[a] + 2.0f * radius_)
                return;
        int64_t own[3], other[3];
        for (int a = 0; a < 3; ++a) {
            const double u = (static_cast<double>(x[a]) - bounds_.min[a]) * inverse_cell_;
            own[a] = static_cast<int64_t>(std::floor(u));
            other[a] = u - static_cast<double>(own[a]) < 0.5 ? own[a] - 1 : own[a] + 1;
        }
        uint32_t visited[8];
        for (int corner = 0; corner < 8; ++corner) {
            const uint32_t b =
                bucket(corner & 1 ? other[0] : own[0], corner & 2 ? other[1] : own[1],
                       corner & 4 ? other[2] : own[2]);
            // Two of the eight cells may share a bucket: search it once.
            bool seen = false;
            for (int k = 0; k < corner; ++k) seen = seen || visited[k] == b;
            visited[corner] = b;
            if (seen) continue;
            for (uint32_t k = bucket_start_[b]; k < bucket_start_[b + 1]; ++k) {
                const Vec3 d = photons_[k].p - x;
                if (glm::dot(d, d) < radius2_) fn(photons_[k]);
            }
        }
    }

private:
    uint32_t bucket(int64_t i, int64_t j, int64_t k) const {
        const uint64_t h = static_cast<uint64_t>(i) * 73856093u ^
                           static_cast<uint64_t>(j) * 19349663u ^
                           static_cast<uint64_t>(k) * 83492791u;
        return static_cast<uint32_t>(h & bucket_mask_);
    }
    uint32_t bucket_of(const Vec3& p) const;

    float radius_ = 0.0f, radius2_ = 0.0f;
    double inverse_cell_ = 0.0;  // 1 / cell size
    Bounds3 bounds_;             // of the photons' positions
    uint64_t bucket_mask_ = 0;   // buckets - 1 (a power of two)
    std::vector<Photon> photons_;
    std::vector<uint32_t> bucket_start_;  // bucket b's photons: [start[b], start[b + 1])
};

}  // namespace lessons
