// Lesson 4's --max-depth and --roulette-after: how long paths may grow, and when Russian
// roulette may end them. Lesson 5 declares the same flags for its subpaths.
#pragma once

namespace CLI {
class App;
}

namespace lessons {

void add_path_length_flags(CLI::App& app, int& max_depth, int& roulette_after);

}  // namespace lessons
