// The 05_bidirectional executable: the lesson (lesson.cpp) run from the command line.
#include "bidirectional.h"

int main(int argc, char** argv) { return lessons::run_lesson(argc, argv, lessons::bidirectional_lesson()); }
