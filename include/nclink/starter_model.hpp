// Starter models: a small, conformant model (probe file) for a lathe, a
// machining center or a generic machine, from a few choices. The place to
// begin a port (`nclink model new`, docs/porting-guide.md): edit names and
// add what the machine has beyond it. Every id the driver serves is listed
// in the returned model's dataItems; the SDK answers the configs.
#pragma once

#include <nclink/export.hpp>
#include <nclink/json.hpp>
#include <nclink/result.hpp>

#include <string>
#include <vector>

namespace nclink {

enum class MachineKind { lathe, machining_center, generic };

struct NCLINK_API StarterModelOptions {
    MachineKind kind = MachineKind::generic;
    /// Device id, also the start of the guid (the terminal id).
    std::string id = "machine";
    std::string name;  ///< default: from the kind
    std::string manufacturer = "ACME";
    /// Linear and rotary axes by table 9 number ("X", "Z", "A", "C"...).
    /// Empty: the kind's usual axes (lathe X Z, machining center X Y Z,
    /// generic none).
    std::vector<std::string> axes;
    /// Spindles, each an AXIS numbered S (S1, S2... for several).
    /// -1: the kind's usual (1; generic 0).
    int spindles = -1;
    /// CNC channels: one CONTROLLER component each (1 = ids without suffix).
    /// 0: no controller (a generic machine without CNC).
    /// -1: the kind's usual (1; generic 0).
    int channels = -1;
    /// Sampling: one SAMPLE_CHANNEL over the axes and spindles, in ms.
    int sample_interval_ms = 10;
    int upload_interval_ms = 1000;
};

/// "lathe", "machining-center" (also "mill", "mc"), "generic".
NCLINK_API Result<MachineKind> machine_kind_from_string(const std::string& text);

/// The model JSON. value_type for choices it cannot build (an axis number
/// not of table 9, a duplicate axis, negative counts).
NCLINK_API Result<Json> make_starter_model(const StarterModelOptions& options);

}  // namespace nclink
