// Lesson 7, section 1: primary sample space (Kelemen, Szirmay-Kalos, Antal and Csonka, "A Simple
// and Robust Mutation Strategy for the Metropolis Light Transport Algorithm", Eurographics 2002).
// Every path lesson 5 makes is a function of the random numbers its walks draw: a point of the
// unit hypercube [0, 1)^n, its primary samples. A Markov chain over those numbers needs no
// knowledge of paths: it changes the numbers, and lesson 5's walks, reading them through the
// RandomNumbers seam (sampling/random_numbers.h), make the path that goes with them.
//
// The state is a vector of numbers, read in order, made on first read. A mutation is lazy: a
// proposal only decides whether it is a large step (every number redrawn uniformly, an
// independent path) or a small step (every number moved by a normal perturbation of standard
// deviation sigma, wrapped around [0, 1)), and a number is changed when the walk reads it. A
// number last changed n small steps ago gets all n at once: the sum of n independent normal
// steps is one normal step of deviation sigma sqrt(n), and wrapping commutes with the sum. A
// number never read since the last accepted large step is first redrawn as that step would have.
// Those catch-up values are the state's own numbers, kept whatever happens to the proposal; the
// proposal's own change (its large step's new value, its small step's one move) is undone on
// rejection, every number read by it getting back the state's value and age, bit for bit.
//
// Numbers are kept in streams (camera, light, connection: MultiplexedPath's), interleaved, so
// that a change in how many numbers one walk reads (a path one bounce longer) does not shift
// the numbers another walk reads.
#pragma once

#include <cstdint>
#include <vector>

#include "sampling/random_numbers.h"
#include "sampling/rng.h"

namespace lessons {

class PrimarySamples {
public:
    // `fresh` draws the numbers the state needs when a number is first read or redrawn.
    PrimarySamples(Rng fresh, float sigma, float large_step_probability, int streams);
    // Its streams refer to it: it stays where it is made.
    PrimarySamples(const PrimarySamples&) = delete;
    PrimarySamples& operator=(const PrimarySamples&) = delete;

    // A proposal: decides, from the chain's own numbers, whether it is a large step, and makes
    // every number read from now on the proposal's. Returns whether it is a large step.
    bool propose();
    // The proposal becomes the state.
    void accept();
    // The state before the proposal comes back, every number read by the proposal restored.
    void reject();
    // The generator that draws the chain's decisions and new numbers from now on (a chain that
    // starts from a bootstrap path keeps the numbers drawn for it and goes on with its own).
    void set_fresh(const Rng& fresh) { fresh_ = fresh; }

    // Before a path is made from the state: every stream reads from its first number again.
    void start_path();
    // Stream k as a source of numbers for a walk.
    RandomNumbers& stream(int k) { return streams_[static_cast<size_t>(k)]; }
    // The next number of stream k.
    float next(int k);

    // For tests: the numbers made so far, in storage order (stream k's i-th number is entry
    // k + streams * i), with the iteration each was last changed at; entries never made are 0
    // and -1.
    struct Entry {
        float value = 0.0f;
        int64_t changed = -1;
    };
    std::vector<Entry> entries() const;
    int64_t iteration() const { return iteration_; }
    bool large_step() const { return large_step_; }

private:
    struct Number {
        float value = 0.0f, saved_value = 0.0f;
        int64_t changed = -1, saved_changed = -1;  // -1: never made
    };
    class Stream final : public RandomNumbers {
    public:
        Stream(PrimarySamples* owner, int index) : owner_(owner), index_(index) {}
        float uniform() override { return owner_->next(index_); }
        Vec2 uniform2() override {
            const float a = uniform();
            return {a, uniform()};
        }

    private:
        PrimarySamples* owner_ = nullptr;
        int index_ = 0;
    };
    // Makes number x, not yet read by this proposal, the proposal's (lazily applying the steps
    // the state's own number missed).
    void bring_up_to_date(Number& x);
    // Moves x by `steps` small steps at once (none if steps <= 0), wrapped around [0, 1).
    void move(Number& x, int64_t steps);

    Rng fresh_;
    float sigma_;
    float large_step_probability_;
    int stream_count_;
    std::vector<Stream> streams_;
    std::vector<int64_t> read_;  // per stream, numbers read since start_path
    std::vector<Number> numbers_;
    // The numbers the proposal has read (and changed): all that a rejection restores, however
    // long the state once was.
    std::vector<size_t> changed_now_;
    int64_t iteration_ = 0;        // the proposal being made (0: the first state)
    int64_t last_large_step_ = 0;  // the iteration of the last accepted large step
    bool large_step_ = true;       // the first state is made of fresh numbers
};

// A sample of the standard normal distribution from two uniform numbers (Box and Muller 1958).
double standard_normal(float u1, float u2);

}  // namespace lessons
