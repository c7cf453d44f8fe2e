#include "sgslam/dynamic/dynamic_config.h"

namespace sgslam {

// The refinements are switches: any value is valid.
void DynamicConfig::Validate(ConfigChecker& c) const {
  c.Check(mode == "none" || mode == "semantic" || mode == "geometric" || mode == "sg", "mode", mode,
          "must be none, semantic, geometric or sg");
  c.InRange("eps_std", eps_std, 1e-3, 100.0);
}

}  // namespace sgslam
