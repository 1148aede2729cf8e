// Compiling and linking an OpenGL program from GLSL sources, for the engine's passes. Needs a current context.
#pragma once

#include <initializer_list>
#include <string>
#include <utility>

namespace fly::raster {

// One program of (GL shader type, source) stages, each prefixed by "#version 450 core" and `defines`.
// std::runtime_error naming `name` with the driver's log when a stage does not compile or the program does
// not link (an internal error: the sources are the engine's own).
unsigned linkGlProgram(const std::string& name, const std::string& defines,
                       std::initializer_list<std::pair<unsigned, const char*>> stages);

}  // namespace fly::raster
