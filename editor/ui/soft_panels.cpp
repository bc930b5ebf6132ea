// Placeholder until the soft panels land: the generic inspector only.
#include "ui/kind_panels.h"

namespace pliant::editor {

const KindPanels& soft_panels() {
  static const KindPanels p{"soft"};
  return p;
}

}  // namespace pliant::editor
