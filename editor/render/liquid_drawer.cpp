// Placeholder until the liquid take drawer lands: draws nothing.
#include "render/frame_drawer.h"

namespace pliant::editor {

std::unique_ptr<FrameDrawer> make_liquid_drawer() { return nullptr; }

}  // namespace pliant::editor
