// Placeholder until the articulated take drawer lands: draws nothing.
#include "render/frame_drawer.h"

namespace pliant::editor {

std::unique_ptr<FrameDrawer> make_articulated_drawer() { return nullptr; }

}  // namespace pliant::editor
