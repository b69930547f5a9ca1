// The MTConnect side of the mapping as data: the component tree of every
// Device (with the generated Axes and Path containers) and the lookup of
// every data object. mtconnect_writer.cpp turns it into XML.
#pragma once

#include "mapping/plan.hpp"

#include <nclink/mapping.hpp>

#include <string>
#include <vector>

namespace nclink {

/// Fills the private members of MtConnectMapping.
struct MtConnectMappingBuilder {
    static std::vector<MtDevice>& devices(MtConnectMapping& m) { return m.devices_; }
    static std::vector<MtDataItem>& items(MtConnectMapping& m) { return m.items_; }
    /// Builds the lookup indexes once the items are complete.
    static void index(MtConnectMapping& m) {
        m.by_item_.clear();
        m.by_id_.clear();
        for (std::size_t i = 0; i < m.items_.size(); ++i) {
            m.by_item_.emplace(m.items_[i].item_id, i);
            if (!m.items_[i].id.empty()) m.by_id_.emplace(m.items_[i].id, i);
        }
    }
};

namespace mapping_detail {

/// Description element of a Device or component (tables A.1 and A.3).
struct MtDescription {
    std::string manufacturer;  ///< NMTOKEN
    std::string model;
    std::string serial_number;
    std::string text;

    bool empty() const { return manufacturer.empty() && model.empty() && serial_number.empty() && text.empty(); }
};

struct MtNode {
    std::string element;  ///< "Linear", "Axes", "Path", ...
    std::string id;
    std::string name;
    MtDescription description;
    std::vector<std::size_t> items;  ///< into MtConnectMapping::items(), DataItems in order
    std::vector<MtNode> children;
};

struct MtDeviceNode {
    std::size_t device = 0;  ///< into MtConnectMapping::devices()
    MtDescription description;
    std::vector<std::size_t> items;  ///< after the AVAILABILITY item
    std::vector<MtNode> components;
};

struct MtPlan {
    Plan plan;  ///< what the lookup was made from (sources point into it)
    MtConnectMapping mapping;
    /// Parallel to mapping.items(): the planned data object of each.
    std::vector<const PlannedItem*> sources;
    std::vector<MtDeviceNode> devices;
    std::vector<UnmappedItem> unmapped;
    std::vector<MappingNote> notes;
};

Result<MtPlan> plan_mtconnect(const Model& model, const MappingOptions& options);

/// The Devices document of a plan.
std::string write_mtconnect(const MtPlan& plan, const MappingOptions& options);

}  // namespace mapping_detail
}  // namespace nclink
