// What a configuration reload did: which changed keys are in effect now and
// which take effect only after a restart. Programs reload on SIGHUP
// (docs/configuration.md, "Reloading"); keys are named by their dotted path
// in the configuration file ("access", "broker.url").
#pragma once

#include <string>
#include <vector>

namespace nclink {

struct ConfigReload {
    std::vector<std::string> applied;         ///< changed keys whose new value is in effect now
    std::vector<std::string> restart_needed;  ///< changed keys kept at their running value until a restart
};

}  // namespace nclink
