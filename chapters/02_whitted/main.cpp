// The 02_whitted executable: the lesson (lesson.cpp) run from the command line.
#include "driver/app.h"

namespace lessons {
Lesson whitted_lesson();  // lesson.cpp
}

int main(int argc, char** argv) {
    return lessons::run_lesson(argc, argv, lessons::whitted_lesson());
}
