// Placeholder until the soft take drawer lands: draws nothing.
#include "render/frame_drawer.h"

namespace pliant::editor {

std::unique_ptr<FrameDrawer> make_soft_drawer() { return nullptr; }

}  // namespace pliant::editor
