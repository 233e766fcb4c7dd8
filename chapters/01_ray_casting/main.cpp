// The 01_ray_casting executable: the lesson (lesson.cpp) run from the command line.
#include "driver/app.h"

namespace lessons {
Lesson ray_casting_lesson();  // lesson.cpp
}

int main(int argc, char** argv) {
    return lessons::run_lesson(argc, argv, lessons::ray_casting_lesson());
}
