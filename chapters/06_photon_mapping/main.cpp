// The 06_photon_mapping executable: the lesson (lesson.cpp) run from the command line.
#include "driver/app.h"

namespace lessons {
Lesson photon_mapping_lesson();  // lesson.cpp
}

int main(int argc, char** argv) {
    return lessons::run_lesson(argc, argv, lessons::photon_mapping_lesson());
}
