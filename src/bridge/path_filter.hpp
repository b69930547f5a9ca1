// MTConnect path= (part 1 8.3: an XPath over the Devices document that
// selects what a Current or Sample request reports). Evaluated by libxml2's
// XPath engine on the bridge's own Devices document, so every XPath 1.0
// form works, e.g. //DataItem[@type="POSITION"], //Axes,
// //Linear[@name="X"]//DataItem[@category="SAMPLE"],
// //Controller//DataItem[@type="EXECUTION"] | //Axes. Element names are
// written without a namespace prefix. A selected DataItem selects itself; a
// selected component or Device selects every DataItem below it.
#pragma once

#include "bridge/request_params.hpp"

#include <optional>
#include <set>
#include <string>

namespace nclink::bridge {

/// Adds to `ids` the id of every DataItem `xpath` selects in `devices_xml`
/// (an MTConnectDevices document). INVALID_PATH when the expression does not
/// parse or selects no element.
std::optional<MtError> select_data_items(const std::string& devices_xml, const std::string& xpath, std::set<std::string>& ids);

}  // namespace nclink::bridge
