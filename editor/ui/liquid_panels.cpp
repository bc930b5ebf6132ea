// Placeholder until the liquid panels land: the generic inspector only.
#include "ui/kind_panels.h"

namespace pliant::editor {

const KindPanels& liquid_panels() {
  static const KindPanels p{"liquid"};
  return p;
}

}  // namespace pliant::editor
