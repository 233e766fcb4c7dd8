// The 04_rendering_equation executable: the lesson (lesson.cpp) run from the command line.
#include "rendering_equation.h"

int main(int argc, char** argv) { return lessons::run_lesson(argc, argv, lessons::rendering_equation_lesson()); }
