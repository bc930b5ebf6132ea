// Placeholder until the articulated panels land: the generic inspector only.
#include "ui/kind_panels.h"

namespace pliant::editor {

const KindPanels& articulated_panels() {
  static const KindPanels p{"articulated"};
  return p;
}

}  // namespace pliant::editor
