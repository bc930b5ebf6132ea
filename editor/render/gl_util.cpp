#include "render/gl_util.h"

#include <vector>

#include "pliant/shaders.h"

namespace pliant::editor::gl {

void destroy_texture(GLuint id) { glDeleteTextures(1, &id); }
void destroy_buffer(GLuint id) { glDeleteBuffers(1, &id); }
void destroy_vertex_array(GLuint id) { glDeleteVertexArrays(1, &id); }
void destroy_program(GLuint id) { glDeleteProgram(id); }

Texture make_texture() {
  GLuint id = 0;
  glGenTextures(1, &id);
  return Texture(id);
}
Buffer make_buffer() {
  GLuint id = 0;
  glGenBuffers(1, &id);
  return Buffer(id);
}
VertexArray make_vertex_array() {
  GLuint id = 0;
  glGenVertexArrays(1, &id);
  return VertexArray(id);
}

namespace {

std::string shader_log(GLuint s) {
  GLint n = 0;
  glGetShaderiv(s, GL_INFO_LOG_LENGTH, &n);
  std::vector<char> log(static_cast<size_t>(n) + 1, '\0');
  glGetShaderInfoLog(s, n, nullptr, log.data());
  return log.data();
}

GLuint compile(GLenum type, const std::string& name, std::string* err) {
  const std::string_view src = pliant::shaders::get(name);
  if (src.empty()) {
    *err = "shader " + name + ": not embedded (is it in shaders/ and was the build re-run?)";
    return 0;
  }
  GLuint s = glCreateShader(type);
  const char* p = src.data();
  const GLint len = static_cast<GLint>(src.size());
  glShaderSource(s, 1, &p, &len);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    *err = "shader " + name + " failed to compile: " + shader_log(s);
    glDeleteShader(s);
    return 0;
  }
  return s;
}

}  // namespace

bool Program::build(const std::string& vs_name, const std::string& fs_name, std::string* err) {
  std::string e;
  GLuint vs = compile(GL_VERTEX_SHADER, vs_name, &e);
  GLuint fs = vs ? compile(GL_FRAGMENT_SHADER, fs_name, &e) : 0;
  if (!vs || !fs) {
    if (vs) glDeleteShader(vs);
    if (err) *err = e;
    return false;
  }
  GLuint p = glCreateProgram();
  glAttachShader(p, vs);
  glAttachShader(p, fs);
  glLinkProgram(p);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint n = 0;
    glGetProgramiv(p, GL_INFO_LOG_LENGTH, &n);
    std::vector<char> log(static_cast<size_t>(n) + 1, '\0');
    glGetProgramInfoLog(p, n, nullptr, log.data());
    if (err) *err = "program " + vs_name + " + " + fs_name + " failed to link: " + log.data();
    glDeleteProgram(p);
    return false;
  }
  id_ = Handle<destroy_program>(p);
  return true;
}

std::string drain_errors() {
  std::string out;
  for (int i = 0; i < 16; ++i) {
    const GLenum e = glGetError();
    if (e == GL_NO_ERROR) break;
    switch (e) {
      case GL_INVALID_ENUM: out += "GL_INVALID_ENUM "; break;
      case GL_INVALID_VALUE: out += "GL_INVALID_VALUE "; break;
      case GL_INVALID_OPERATION: out += "GL_INVALID_OPERATION "; break;
      case GL_INVALID_FRAMEBUFFER_OPERATION: out += "GL_INVALID_FRAMEBUFFER_OPERATION "; break;
      case GL_OUT_OF_MEMORY: out += "GL_OUT_OF_MEMORY "; break;
      default: out += "GL error " + std::to_string(e) + " ";
    }
  }
  return out;
}

}  // namespace pliant::editor::gl
