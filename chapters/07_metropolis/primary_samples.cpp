// Lesson 7, section 1: primary sample space (see primary_samples.h).
#include "07_metropolis/primary_samples.h"

#include <cmath>

namespace lessons {

PrimarySamples::PrimarySamples(Rng fresh, float sigma, float large_step_probability, int streams)
    : fresh_(fresh),
      sigma_(sigma),
      large_step_probability_(large_step_probability),
      stream_count_(streams),
      read_(static_cast<size_t>(streams), 0) {
    streams_.reserve(static_cast<size_t>(streams));
    for (int k = 0; k < streams; ++k) streams_.emplace_back(this, k);
}

bool PrimarySamples::propose() {
    ++iteration_;
    large_step_ = fresh_.uniform() < large_step_probability_;
    return large_step_;
}

void PrimarySamples::accept() {
    if (large_step_) last_large_step_ = iteration_;
}

void PrimarySamples::reject() {
    for (Number& x : numbers_)
        if (x.changed == iteration_) {
            x.value = x.saved_value;
            x.changed = x.saved_changed;
        }
    // The iteration counts accepted proposals only: a number that the rejected proposal did not
    // read has missed no step.
    --iteration_;
}

void PrimarySamples::start_path() {
    for (int64_t& r : read_) r = 0;
}

float PrimarySamples::next(int k) {
    const size_t i =
        static_cast<size_t>(k) +
        static_cast<size_t>(stream_count_) * static_cast<size_t>(read_[static_cast<size_t>(k)]++);
    if (i >= numbers_.size()) numbers_.resize(i + 1);
    Number& x = numbers_[i];
    bring_up_to_date(x);
    return x.value;
}

void PrimarySamples::bring_up_to_date(Number& x) {
    if (x.changed == iteration_) return;  // already read by this proposal
    x.saved_value = x.value;
    x.saved_changed = x.changed;
    if (large_step_) {
        x.value = fresh_.uniform();
    } else {
        // Not read since the last accepted large step (or never): first as that step made it.
        if (x.changed < last_large_step_) {
            x.value = fresh_.uniform();
            x.changed = last_large_step_;
        }
        // Then every accepted small step since, at once.
        const int64_t steps = iteration_ - x.changed;
        if (steps > 0) {
            const float u1 = fresh_.uniform();
            const float u2 = fresh_.uniform();
            const double moved =
                static_cast<double>(x.value) + static_cast<double>(sigma_) *
                                                   std::sqrt(static_cast<double>(steps)) *
                                                   standard_normal(u1, u2);
            float wrapped = static_cast<float>(moved - std::floor(moved));
            if (wrapped >= 1.0f) wrapped = 0.0f;  // 1 - 2^-60 rounds up: the same point as 0
            x.value = wrapped;
        }
    }
    x.changed = iteration_;
}

std::vector<PrimarySamples::Entry> PrimarySamples::entries() const {
    std::vector<Entry> out;
    out.reserve(numbers_.size());
    for (const Number& x : numbers_) out.push_back({x.value, x.changed});
    return out;
}

double standard_normal(float u1, float u2) {
    const double r = std::sqrt(-2.0 * std::log(1.0 - static_cast<double>(u1)));
    return r * std::cos(2.0 * 3.14159265358979323846 * static_cast<double>(u2));
}

}  // namespace lessons
