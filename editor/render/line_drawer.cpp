#include "render/line_drawer.h"

#include <cstddef>

namespace pliant::editor {

bool LineDrawer::init(std::string* err) {
  if (!program_.build("lines.vert", "lines.frag", err)) return false;
  vao_ = gl::make_vertex_array();
  vbo_ = gl::make_buffer();
  glBindVertexArray(vao_.get());
  glBindBuffer(GL_ARRAY_BUFFER, vbo_.get());
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(Vertex),
                        reinterpret_cast<const void*>(offsetof(Vertex, pos)));
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, sizeof(Vertex),
                        reinterpret_cast<const void*>(offsetof(Vertex, color)));
  glBindVertexArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
  return true;
}

void LineDrawer::add(const Vec3& a, const Vec3& b, const Color& c) {
  verts_.push_back({{a[0], a[1], a[2]}, {c[0], c[1], c[2], c[3]}});
  verts_.push_back({{b[0], b[1], b[2]}, {c[0], c[1], c[2], c[3]}});
}

void LineDrawer::add_box(const Vec3& lo, const Vec3& hi, const Color& c) {
  auto corner = [&](int i) { return Vec3{(i & 1) ? hi[0] : lo[0], (i & 2) ? hi[1] : lo[1], (i & 4) ? hi[2] : lo[2]}; };
  for (int i = 0; i < 8; ++i)
    for (int bit = 1; bit < 8; bit <<= 1)
      if (!(i & bit)) add(corner(i), corner(i | bit), c);
}

void LineDrawer::draw(const Mat4& mvp) {
  if (verts_.empty() || !program_) return;
  program_.use();
  program_.set("u_mvp", mvp);
  glBindVertexArray(vao_.get());
  glBindBuffer(GL_ARRAY_BUFFER, vbo_.get());
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(verts_.size() * sizeof(Vertex)), verts_.data(),
               GL_STREAM_DRAW);
  glDrawArrays(GL_LINES, 0, static_cast<GLsizei>(verts_.size()));
  glBindBuffer(GL_ARRAY_BUFFER, 0);
  glBindVertexArray(0);
  verts_.clear();
}

void LineDrawer::shutdown() {
  program_.reset();
  vbo_.reset();
  vao_.reset();
  verts_.clear();
}

}  // namespace pliant::editor
