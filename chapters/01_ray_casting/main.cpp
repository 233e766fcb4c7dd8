// The 01_ray_casting executable: the lesson (lesson.cpp) run from the command line.
#include "ray_casting.h"

int main(int argc, char** argv) { return lessons::run_lesson(argc, argv, lessons::ray_casting_lesson()); }
