#pragma once
// Compiles and links one GLSL 330 program from a vertex and a fragment shader; 0 and `error` on failure.
#include <string>

namespace hmp::view::gl {

unsigned link_program(const char* vertex_source, const char* fragment_source, std::string& error);

}  // namespace hmp::view::gl
