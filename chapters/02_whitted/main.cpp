// The 02_whitted executable: the lesson (lesson.cpp) run from the command line.
#include "whitted.h"

int main(int argc, char** argv) { return lessons::run_lesson(argc, argv, lessons::whitted_lesson()); }
