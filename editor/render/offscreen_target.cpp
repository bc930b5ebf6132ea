#include "render/offscreen_target.h"

#include <GL/gl.h>
#include <GL/glext.h>

namespace pliant::editor {

bool OffscreenTarget::ensure(int width, int height) {
  if (fbo && w == width && h == height) return false;
  if (!fbo) {
    glGenFramebuffers(1, &fbo);
    glGenTextures(1, &color_tex);
    glGenRenderbuffers(1, &depth_rb);
  }
  glBindTexture(GL_TEXTURE_2D, color_tex);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glBindTexture(GL_TEXTURE_2D, 0);
  // Depth for the mesh drawers (soft characters, articulated bodies, containers).
  glBindRenderbuffer(GL_RENDERBUFFER, depth_rb);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, width, height);
  glBindRenderbuffer(GL_RENDERBUFFER, 0);
  GLint prev = 0;
  glGetIntegerv(GL_FRAMEBUFFER_BINDING, &prev);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, color_tex, 0);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, depth_rb);
  glBindFramebuffer(GL_FRAMEBUFFER, GLuint(prev));
  w = width;
  h = height;
  return true;
}

void OffscreenTarget::release() {
  if (fbo) glDeleteFramebuffers(1, &fbo);
  if (color_tex) glDeleteTextures(1, &color_tex);
  if (depth_rb) glDeleteRenderbuffers(1, &depth_rb);
  fbo = color_tex = depth_rb = 0;
  w = h = 0;
}

void OffscreenTarget::bind() const {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glViewport(0, 0, w, h);
}

}  // namespace pliant::editor
