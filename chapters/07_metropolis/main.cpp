// The 07_metropolis executable: the lesson (lesson.cpp) run from the command line.
#include "driver/app.h"

namespace lessons {
Lesson metropolis_lesson();  // lesson.cpp
}

int main(int argc, char** argv) {
    return lessons::run_lesson(argc, argv, lessons::metropolis_lesson());
}
