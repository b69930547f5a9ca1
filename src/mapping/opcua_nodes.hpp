// The OPC UA side of the mapping as data: nodes with their references, in
// the order the NodeSet2 file lists them. opcua_writer.cpp writes them.
#pragma once

#include "mapping/plan.hpp"

#include <nclink/mapping.hpp>

#include <cstddef>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace nclink {

/// Fills the private members of OpcUaMapping.
struct OpcUaMappingBuilder {
    static std::vector<UaNamespace>& namespaces(OpcUaMapping& m) { return m.namespaces_; }
    static std::vector<UaVariable>& variables(OpcUaMapping& m) { return m.variables_; }
    /// Builds the lookup index once the variables are complete.
    static void index(OpcUaMapping& m) {
        m.by_item_.clear();
        for (std::size_t i = 0; i < m.variables_.size(); ++i) m.by_item_.emplace(m.variables_[i].item_id, i);
    }
};

namespace mapping_detail {

/// A Value element's content (Opc.Ua.Types.xsd encodings).
struct UaValue {
    enum class Kind {
        none,
        boolean,
        int32,
        uint32,
        number,  ///< Double
        string,
        localized,       ///< LocalizedText
        localized_list,  ///< ListOfLocalizedText
        eu_information,  ///< ExtensionObject EUInformation
        range,           ///< ExtensionObject Range
        node_id,
    };
    Kind kind = Kind::none;
    bool flag = false;
    long long integer = 0;
    double number = 0;
    double low = 0;
    double high = 0;
    std::string text;
    std::vector<std::string> list;
    const UnitRow* unit = nullptr;
};

struct UaReference {
    std::string type;    ///< alias ("HasComponent") or NodeId
    std::string target;  ///< NodeId
    bool forward = true;
};

enum class UaNodeClass { object, variable, object_type };

struct UaNode {
    UaNodeClass node_class = UaNodeClass::object;
    std::string node_id;
    std::string browse_name;  ///< "1:X axis", "EngineeringUnits"
    std::string display_name;
    std::string description;
    std::string parent;     ///< ParentNodeId ("" = none)
    std::string data_type;  ///< variables
    int value_rank = -1;
    std::string array_dimensions;
    int access_level = 1;
    double minimum_sampling_interval = 0;
    bool is_abstract = false;
    std::vector<UaReference> references;
    UaValue value;
    /// Attributes of the <nclink:Item> extension (name, value), empty = none.
    std::vector<std::pair<std::string, std::string>> extension;
};

/// Namespace-0 NodeIds used by the mapping.
namespace ua {
inline constexpr std::string_view objects_folder = "i=85";
inline constexpr std::string_view base_object_type = "i=58";
inline constexpr std::string_view folder_type = "i=61";
inline constexpr std::string_view base_data_variable_type = "i=63";
inline constexpr std::string_view property_type = "i=68";
inline constexpr std::string_view mandatory = "i=78";
inline constexpr std::string_view optional = "i=80";
inline constexpr std::string_view data_item_type = "i=2365";
inline constexpr std::string_view analog_item_type = "i=2368";
inline constexpr std::string_view two_state_type = "i=2373";
inline constexpr std::string_view multi_state_type = "i=2376";
}  // namespace ua

/// "ns=<ns>;s=<id>" / "ns=<ns>;i=<n>".
std::string string_node_id(int ns, std::string_view id);
std::string numeric_node_id(int ns, int id);
/// "<ns>:<name>".
std::string qualified(int ns, std::string_view name);

/// Collects nodes; keeps NodeIds unique and both directions of a reference.
class UaNodeList {
public:
    /// Adds a node; returns its index. A NodeId used twice is recorded as
    /// the collision (first one wins) and the node is still added.
    std::size_t add(UaNode node);
    UaNode& at(std::size_t index) { return nodes_[index]; }
    const UaNode& at(std::size_t index) const { return nodes_[index]; }
    const std::vector<UaNode>& nodes() const noexcept { return nodes_; }
    /// A forward reference source -> target and its inverse; hierarchical
    /// references also set the target's ParentNodeId when it has none.
    void link(std::size_t source, std::size_t target, std::string_view type);
    /// A one-sided reference (to a node of another nodeset).
    void reference(std::size_t source, std::string_view type, std::string target, bool forward);
    /// The first NodeId that was added twice, "" when none.
    const std::string& collision() const noexcept { return collision_; }

private:
    std::vector<UaNode> nodes_;
    std::unordered_map<std::string, std::size_t> index_;
    std::string collision_;
};

/// The whole OPC UA document as data.
struct UaDocument {
    Plan plan;
    OpcUaMapping mapping;
    UaNodeList nodes;
    std::vector<std::pair<std::string, std::string>> aliases;  ///< alias, NodeId
    std::vector<UnmappedItem> unmapped;
    std::vector<MappingNote> notes;
    int cnc_namespace = 0;  ///< index of the CNC namespace, 0 = basic profile
};

Result<UaDocument> plan_opcua(const Model& model, const MappingOptions& options);
std::string write_opcua(const UaDocument& document, const MappingOptions& options);

}  // namespace mapping_detail
}  // namespace nclink
