// Lesson 6, section 1: the hashed grid of photons (see photon_map.h).
#include "06_photon_mapping/photon_map.h"

#include <algorithm>
#include <bit>
#include <stdexcept>

#include "accel/parallel.h"

namespace lessons {

uint32_t PhotonGrid::bucket_of(const Vec3& p) const {
    int64_t cell[3];
    for (int a = 0; a < 3; ++a)
        cell[a] = static_cast<int64_t>(
            std::floor((static_cast<double>(p[a]) - bounds_.min[a]) * inverse_cell_));
    return bucket(cell[0], cell[1], cell[2]);
}

PhotonGrid::PhotonGrid(std::span<const Photon> photons, float radius, int threads, size_t buckets) {
    if (!(radius > 0.0f) || !std::isfinite(radius))
        throw std::invalid_argument("PhotonGrid: the radius must be positive and finite");
    radius_ = radius;
    radius2_ = radius * radius;
    // Cells of 2r: a ball of radius r meets two of them along each axis (photon_map.h).
    inverse_cell_ = 1.0 / (2.0 * static_cast<double>(radius) * (1.0 + 0x1p-10));
    for (const Photon& photon : photons)
        if (is_finite(photon.p)) bounds_.expand(photon.p);
    if (bounds_.empty()) return;
    const size_t wanted = buckets > 0 ? buckets : photons.size();
    bucket_mask_ = std::bit_ceil(std::clamp<size_t>(wanted, 1, size_t(1) << 31)) - 1;

    // Each photon's bucket, on several threads (each photon's alone: the same for any number);
    // bucket_mask_ + 1 marks a photon left out.
    const uint32_t left_out = static_cast<uint32_t>(bucket_mask_ + 1);
    std::vector<uint32_t> bucket_index(photons.size());
    parallel_parts(photons.size(), threads, 65536, [&](size_t begin, size_t end, int) {
        for (size_t k = begin; k < end; ++k)
            bucket_index[k] = is_finite(photons[k].p) ? bucket_of(photons[k].p) : left_out;
    });

    // The counting sort, in the photons' order: how many per bucket, where each bucket starts
    // (the running sum), then each photon into the next free place of its bucket (stable).
    bucket_start_.assign(static_cast<size_t>(bucket_mask_) + 2, 0);
    for (const uint32_t b : bucket_index)
        if (b != left_out) ++bucket_start_[b + 1];
    for (size_t b = 1; b < bucket_start_.size(); ++b) bucket_start_[b] += bucket_start_[b - 1];
    photons_.resize(bucket_start_.back());
    std::vector<uint32_t> next(bucket_start_.begin(), bucket_start_.end() - 1);
    for (size_t k = 0; k < photons.size(); ++k)
        if (bucket_index[k] != left_out) photons_[next[bucket_index[k]]++] = photons[k];
}

}  // namespace lessons
