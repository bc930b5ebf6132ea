// Small OpenGL 3.3 core helpers: move-only owners of GL objects and shader
// programs built from the embedded GLSL (pliant/shaders.h) with the driver's
// info log in the error message.
#pragma once
#include <GL/gl.h>
#include <GL/glext.h>

#include <string>
#include <utility>

#include "render/mat4.h"

namespace pliant::editor::gl {

// Owner of one GL name; Destroy is a function `void(GLuint)`.
template <void (*Destroy)(GLuint)>
class Handle {
 public:
  Handle() = default;
  explicit Handle(GLuint id) : id_(id) {}
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& o) noexcept : id_(std::exchange(o.id_, 0)) {}
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = std::exchange(o.id_, 0);
    }
    return *this;
  }
  ~Handle() { reset(); }
  void reset() {
    if (id_) Destroy(id_);
    id_ = 0;
  }
  GLuint get() const { return id_; }
  explicit operator bool() const { return id_ != 0; }

 private:
  GLuint id_ = 0;
};

void destroy_texture(GLuint id);
void destroy_buffer(GLuint id);
void destroy_vertex_array(GLuint id);
void destroy_program(GLuint id);

using Texture = Handle<destroy_texture>;
using Buffer = Handle<destroy_buffer>;
using VertexArray = Handle<destroy_vertex_array>;

Texture make_texture();
Buffer make_buffer();
VertexArray make_vertex_array();

class Program {
 public:
  // Compiles and links the embedded shaders `vs_name` and `fs_name`; false with
  // *err = "<file>: <info log>" on failure.
  bool build(const std::string& vs_name, const std::string& fs_name, std::string* err);
  void use() const { glUseProgram(id_.get()); }
  GLint uniform(const char* name) const { return glGetUniformLocation(id_.get(), name); }
  void set(const char* name, float v) const { glUniform1f(uniform(name), v); }
  void set(const char* name, int v) const { glUniform1i(uniform(name), v); }
  void set(const char* name, float x, float y) const { glUniform2f(uniform(name), x, y); }
  void set(const char* name, float x, float y, float z) const { glUniform3f(uniform(name), x, y, z); }
  void set(const char* name, const Mat4& m) const { glUniformMatrix4fv(uniform(name), 1, GL_FALSE, m.data()); }
  explicit operator bool() const { return static_cast<bool>(id_); }
  void reset() { id_.reset(); }

 private:
  Handle<destroy_program> id_;
};

// Drains glGetError(); returns "" or a list like "GL_INVALID_ENUM ...".
std::string drain_errors();

}  // namespace pliant::editor::gl
