#include "raster/gl_program.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <stdexcept>
#include <vector>

#include "base/log.h"

namespace fly::raster {
namespace {

unsigned compileStage(GLenum type, const std::string& source, const std::string& name) {
  const GLuint s = glCreateShader(type);
  const char* text = source.c_str();
  glShaderSource(s, 1, &text, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    glGetShaderiv(s, GL_INFO_LOG_LENGTH, &length);
    std::string info(size_t(std::max(length, 1)), '\0');
    glGetShaderInfoLog(s, length, nullptr, info.data());
    glDeleteShader(s);
    throw std::runtime_error("internal error: shader " + name + " does not compile: " + info);
  }
  return s;
}

}  // namespace

unsigned linkGlProgram(const std::string& name, const std::string& defines,
                       std::initializer_list<std::pair<unsigned, const char*>> stages) {
  const std::string head = "#version 450 core\n" + defines;
  std::vector<GLuint> shaders;
  try {
    for (const auto& [type, source] : stages) shaders.push_back(compileStage(type, head + source, name));
  } catch (...) {
    for (GLuint sh : shaders) glDeleteShader(sh);
    throw;
  }
  const GLuint p = glCreateProgram();
  for (GLuint sh : shaders) glAttachShader(p, sh);
  glLinkProgram(p);
  for (GLuint sh : shaders) glDeleteShader(sh);
  GLint ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    glGetProgramiv(p, GL_INFO_LOG_LENGTH, &length);
    std::string info(size_t(std::max(length, 1)), '\0');
    glGetProgramInfoLog(p, length, nullptr, info.data());
    glDeleteProgram(p);
    throw std::runtime_error("internal error: program " + name + " does not link: " + info);
  }
  log::debug("compiled GL program " + name);
  return p;
}

}  // namespace fly::raster
