// With no EGL vendor library, the EGL platform fails with a message that says
// what is missing. Its own binary: GLVND reads the vendor list at the first EGL
// call of the process, so the environment must be set before anything else.
#include <gtest/gtest.h>

#include <cstdlib>

#include "platform/platform.h"

namespace {

TEST(EglUnavailable, InitFailsWithAClearMessage) {
  setenv("__EGL_VENDOR_LIBRARY_FILENAMES", "/nonexistent/pliant_no_vendor.json", 1);
  auto platform = pliant::editor::make_egl_platform();
  pliant::editor::PlatformOptions opt;
  opt.width = 64;
  opt.height = 64;
  std::string err;
  EXPECT_FALSE(platform->init(opt, &err));
  EXPECT_NE(err.find("EGL headless platform"), std::string::npos) << err;
  EXPECT_NE(err.find("EGL"), std::string::npos) << err;
  EXPECT_GT(err.size(), 40u) << err;  // says what was tried, not just "failed"
  std::printf("message: %s\n", err.c_str());
  platform->shutdown();  // safe after a failed init
}

}  // namespace
