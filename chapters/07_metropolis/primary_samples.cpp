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
    changed_now_.clear();
    large_step_ = fresh_.uniform() < large_step_probability_;
    return large_step_;
}

void PrimarySamples::accept() {
    if (large_step_) last_large_step_ = iteration_;
}

void PrimarySamples::reject() {
    for (const size_t i : changed_now_) {
        Number& x = numbers_[i];
        x.value = x.saved_value;
        x.changed = x.saved_changed;
    }
    changed_now_.clear();
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
    if (x.changed != iteration_) {
        bring_up_to_date(x);
        changed_now_.push_back(i);
    }
    return x.value;
}

void PrimarySamples::bring_up_to_date(Number& x) {
    if (large_step_) {
        // The proposal's number, independent of the state's: the state's own stays as it was,
        // made or not.
        x.saved_value = x.value;
        x.saved_changed = x.changed;
        x.value = fresh_.uniform();
        x.changed = iteration_;
        return;
    }
    // A small step moves the state's own number: first make that number as the state holds it,
    // which stays the state's whether the proposal is accepted or not (drawing it afresh after a
    // rejection would give the proposals that read it a new try each time, and bias the chain
    // towards them). Not read since the last accepted large step (or never): as that step made
    // it; then every accepted small step since, at once.
    if (x.changed < last_large_step_) {
        x.value = fresh_.uniform();
        x.changed = last_large_step_;
    }
    move(x, iteration_ - 1 - x.changed);
    x.changed = iteration_ - 1;
    // Then the proposal's own step, undone on rejection.
    x.saved_value = x.value;
    x.saved_changed = x.changed;
    move(x, 1);
    x.changed = iteration_;
}

void PrimarySamples::move(Number& x, int64_t steps) {
    if (steps <= 0) return;
    const float u1 = fresh_.uniform();
    const float u2 = fresh_.uniform();
    const double moved = static_cast<double>(x.value) + static_cast<double>(sigma_) *
                                                            std::sqrt(static_cast<double>(steps)) *
                                                            standard_normal(u1, u2);
    float wrapped = static_cast<float>(moved - std::floor(moved));
    if (wrapped >= 1.0f) wrapped = 0.0f;  // just below a whole number rounds up: the same as 0
    x.value = wrapped;
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
