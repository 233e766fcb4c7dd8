// The plumbing every lesson shares: command line, scene loading, rendering, writing the image
// and the report. A lesson's main() describes the lesson and its illumination model; this runs
// it, step by step (app.cpp): read the command line, load the scene, read the reference, make
// the model (driver/run.h), render (render/progressive.h), measure, write (run_outputs.h).
#pragma once

#include "driver/lesson.h"
#include "driver/run.h"

namespace lessons {

// Parses the command line, renders, writes <out>.exr, <out>.png and the report (a part, with
// --samples or --pixels, writes its part EXR instead: farm/part.h).
// Exit codes: 0 done; 1 a failure while writing output; 2 bad input (command line, scene file,
// mesh), reported on one line naming the file, line and field.
int run_lesson(int argc, char** argv, const Lesson& lesson);

}  // namespace lessons
