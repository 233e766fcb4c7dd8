// The 05_bidirectional executable: the lesson (lesson.cpp) run from the command line.
#include "driver/app.h"

namespace lessons {
Lesson bidirectional_lesson();  // lesson.cpp
}

int main(int argc, char** argv) {
    return lessons::run_lesson(argc, argv, lessons::bidirectional_lesson());
}
