"use strict";
// A handmade NodeSet2 for one device, shaped the way nclink's mapping writes
// them (GB/T 39561.3 appendix B; docs/opcua.md "What a client sees"): one
// namespace urn:nclink:device:<dev>, the device object s=<dev> organized by
// Objects (i=85), components s=<component id>, items s=<item id> with an
// nclink:Item extension, AccessLevel 3 when setable, properties
// s=<id>.EngineeringUnits / .EnumStrings / .TrueState / .FalseState.

const esc = (s) => String(s).replace(/&/g, "&amp;").replace(/</g, "&lt;").replace(/>/g, "&gt;").replace(/"/g, "&quot;");

const TYPE_DEFINITION = { scalar: "i=63", json: "i=63", enum_index: "i=2376", two_state: "i=2373", analog: "i=2368" };

const lt = (text) => `<uax:LocalizedText><uax:Locale>en</uax:Locale><uax:Text>${esc(text)}</uax:Text></uax:LocalizedText>`;

function property(parent, name, dataType, valueXml, extra = "") {
  return `  <UAVariable NodeId="ns=1;s=${esc(parent)}.${name}" BrowseName="${name}" ParentNodeId="ns=1;s=${esc(parent)}" DataType="${dataType}"${extra}>
    <DisplayName>${name}</DisplayName>
    <References>
      <Reference ReferenceType="HasProperty" IsForward="false">ns=1;s=${esc(parent)}</Reference>
      <Reference ReferenceType="HasTypeDefinition">i=68</Reference>
    </References>
    <Value>${valueXml}</Value>
  </UAVariable>
`;
}

function euInformation(unit) {
  return `<uax:ExtensionObject><uax:TypeId><uax:Identifier>i=888</uax:Identifier></uax:TypeId><uax:Body><uax:EUInformation>
<uax:NamespaceUri>http://www.opcfoundation.org/UA/units/un/cefact</uax:NamespaceUri><uax:UnitId>${unit.code}</uax:UnitId>
<uax:DisplayName><uax:Locale>en</uax:Locale><uax:Text>${esc(unit.text)}</uax:Text></uax:DisplayName>
<uax:Description><uax:Locale>en</uax:Locale><uax:Text>${esc(unit.text)}</uax:Text></uax:Description>
</uax:EUInformation></uax:Body></uax:ExtensionObject>`;
}

/// item: {id, name, dataType, encoding, setable, datatype ("single"|"list"|"dict"),
///        enumStrings, trueState, falseState, unit {code, text}, fixed (XML of a Value), msi}
function variable(component, item, extensions) {
  const props = [];
  const refs = [];
  if (item.unit) refs.push(`<Reference ReferenceType="HasProperty">ns=1;s=${esc(item.id)}.EngineeringUnits</Reference>`);
  if (item.enumStrings) refs.push(`<Reference ReferenceType="HasProperty">ns=1;s=${esc(item.id)}.EnumStrings</Reference>`);
  if (item.trueState !== undefined) refs.push(`<Reference ReferenceType="HasProperty">ns=1;s=${esc(item.id)}.TrueState</Reference>`, `<Reference ReferenceType="HasProperty">ns=1;s=${esc(item.id)}.FalseState</Reference>`);
  if (item.unit) props.push(property(item.id, "EngineeringUnits", "EUInformation", euInformation(item.unit)));
  if (item.enumStrings)
    props.push(property(item.id, "EnumStrings", "LocalizedText", `<uax:ListOfLocalizedText>${item.enumStrings.map(lt).join("")}</uax:ListOfLocalizedText>`, ` ValueRank="1" ArrayDimensions="${item.enumStrings.length}"`));
  if (item.trueState !== undefined) {
    props.push(property(item.id, "TrueState", "LocalizedText", lt(item.trueState)));
    props.push(property(item.id, "FalseState", "LocalizedText", lt(item.falseState)));
  }
  const access = item.setable ? ` AccessLevel="3" UserAccessLevel="3"` : "";
  const msi = item.msi !== undefined ? ` MinimumSamplingInterval="${item.msi}"` : "";
  const typeDef = TYPE_DEFINITION[item.unit ? "analog" : item.encoding || "scalar"];
  const ext = extensions
    ? `
    <Extensions>
      <Extension>
        <nclink:Item xmlns:nclink="urn:nclink:mapping" id="${esc(item.id)}" type="${esc(item.type || "X")}" datatype="${item.datatype || "single"}" setable="${Boolean(item.setable)}" encoding="${item.encoding || "scalar"}"/>
      </Extension>
    </Extensions>`
    : "";
  return `  <UAVariable NodeId="ns=1;s=${esc(item.id)}" BrowseName="1:${esc(item.name || item.id)}" ParentNodeId="ns=1;s=${esc(component)}" DataType="${item.dataType}"${access}${msi}>
    <DisplayName>${esc(item.name || item.id)}</DisplayName>
    <References>
      <Reference ReferenceType="HasComponent" IsForward="false">ns=1;s=${esc(component)}</Reference>
      <Reference ReferenceType="HasTypeDefinition">${typeDef}</Reference>
      ${refs.join("\n      ")}
    </References>${ext}${item.fixed ? `\n    <Value>${item.fixed}</Value>` : ""}
  </UAVariable>
${props.join("")}`;
}

const CNC_URI = "http://opcfoundation.org/UA/CNC";
const CNC_AXIS_TYPE = "ns=2;i=1004"; // CncAxisType of OPC 40502

/// device: {dev, name, components: [{id, name, cncAxis, items: [...]}]};
/// extensions: write the nclink:Item extensions (true, as nclink's mapping
/// does); cnc: the profile cnc form, with components typed from OPC 40502.
function makeNodeset(device, { extensions = true, cnc = false } = {}) {
  const dev = device.dev;
  const parts = [];
  parts.push(`<?xml version="1.0" encoding="UTF-8"?>
<!-- handmade test nodeset, shaped like nclink's mapping output -->
<UANodeSet xmlns="http://opcfoundation.org/UA/2011/03/UANodeSet.xsd" xmlns:uax="http://opcfoundation.org/UA/2008/02/Types.xsd">
  <NamespaceUris>
    <Uri>urn:nclink:device:${esc(dev)}</Uri>${cnc ? `\n    <Uri>${CNC_URI}</Uri>` : ""}
  </NamespaceUris>
  <Models>
    <Model ModelUri="urn:nclink:device:${esc(dev)}" Version="1.0.0" PublicationDate="2024-01-01T00:00:00Z">
      <RequiredModel ModelUri="http://opcfoundation.org/UA/" Version="1.04" PublicationDate="2019-05-01T00:00:00Z"/>${cnc ? `\n      <RequiredModel ModelUri="${CNC_URI}" Version="1.0.0" PublicationDate="2017-06-19T16:01:03Z"/>` : ""}
    </Model>
  </Models>
  <Aliases>
    <Alias Alias="Boolean">i=1</Alias>
    <Alias Alias="Int32">i=6</Alias>
    <Alias Alias="UInt32">i=7</Alias>
    <Alias Alias="Double">i=11</Alias>
    <Alias Alias="String">i=12</Alias>
    <Alias Alias="LocalizedText">i=21</Alias>
    <Alias Alias="BaseDataType">i=24</Alias>
    <Alias Alias="EUInformation">i=887</Alias>
    <Alias Alias="Organizes">i=35</Alias>
    <Alias Alias="HasTypeDefinition">i=40</Alias>
    <Alias Alias="HasProperty">i=46</Alias>
    <Alias Alias="HasComponent">i=47</Alias>
  </Aliases>
  <UAObject NodeId="ns=1;s=${esc(dev)}" BrowseName="1:${esc(device.name || dev)}">
    <DisplayName>${esc(device.name || dev)}</DisplayName>
    <References>
      <Reference ReferenceType="HasTypeDefinition">i=58</Reference>
      <Reference ReferenceType="Organizes" IsForward="false">i=85</Reference>
      <Reference ReferenceType="HasComponent">ns=1;s=${esc(dev)}.Availability</Reference>
      ${device.components.map((c) => `<Reference ReferenceType="HasComponent">ns=1;s=${esc(c.id)}</Reference>`).join("\n      ")}
    </References>
  </UAObject>
  <UAVariable NodeId="ns=1;s=${esc(dev)}.Availability" BrowseName="1:Availability" ParentNodeId="ns=1;s=${esc(dev)}" DataType="String">
    <DisplayName>Availability</DisplayName>
    <References>
      <Reference ReferenceType="HasComponent" IsForward="false">ns=1;s=${esc(dev)}</Reference>
      <Reference ReferenceType="HasTypeDefinition">i=63</Reference>
    </References>
  </UAVariable>
`);
  for (const c of device.components) {
    parts.push(`  <UAObject NodeId="ns=1;s=${esc(c.id)}" BrowseName="1:${esc(c.name || c.id)}" ParentNodeId="ns=1;s=${esc(dev)}">
    <DisplayName>${esc(c.name || c.id)}</DisplayName>
    <References>
      <Reference ReferenceType="HasComponent" IsForward="false">ns=1;s=${esc(dev)}</Reference>
      <Reference ReferenceType="HasTypeDefinition">${cnc && c.cncAxis ? CNC_AXIS_TYPE : "i=58"}</Reference>
      ${c.items.map((i) => `<Reference ReferenceType="HasComponent">ns=1;s=${esc(i.id)}</Reference>`).join("\n      ")}
    </References>
  </UAObject>
`);
    for (const item of c.items) parts.push(variable(c.id, item, extensions));
  }
  parts.push("</UANodeSet>\n");
  return parts.join("");
}

/// The test device: one item per value path of lib/values.js.
function testDevice(dev = "fake-mill-1", { extraItems = [] } = {}) {
  return {
    dev,
    name: "Fake mill",
    components: [
      {
        id: "axis_x",
        name: "X axis",
        cncAxis: true,
        items: [{ id: "x_position", name: "X position", dataType: "Double", unit: { code: 5066068, text: "mm" }, msi: 0, type: "POSITION" }],
      },
      {
        id: "spindle",
        name: "Spindle",
        items: [
          { id: "spindle_override", dataType: "Double", setable: true, unit: { code: 20529, text: "%" }, type: "SPINDLE_OVERRIDE" },
          { id: "spindle_mode", dataType: "UInt32", encoding: "enum_index", enumStrings: ["forward", "stop", "reverse"], setable: true, type: "SPINDLE_MODE" },
          { id: "spindle_max_speed", dataType: "Double", fixed: "<uax:Double>12000</uax:Double>", type: "UPPER_LIMIT" },
        ],
      },
      {
        id: "controller",
        name: "Controller",
        items: [
          { id: "status", dataType: "UInt32", encoding: "enum_index", enumStrings: ["running", "free", "holding"], type: "STATUS" },
          { id: "work_mode", dataType: "Boolean", encoding: "two_state", trueState: "auto", falseState: "manual", setable: true, type: "WORK_MODE" },
          { id: "door_closed", dataType: "Boolean", encoding: "two_state", trueState: "closed", falseState: "open", type: "DOOR_CLOSED" },
          { id: "tool_number", dataType: "Int32", setable: true, type: "TOOL_NUMBER" },
          { id: "program", dataType: "String", setable: true, type: "PROGRAM" },
          { id: "parameters", dataType: "String", encoding: "json", datatype: "dict", setable: true, type: "PARAMETER" },
          { id: "warning", dataType: "String", encoding: "json", type: "WARNING" },
          ...extraItems,
        ],
      },
    ],
  };
}

function itemIds(device) {
  return device.components.flatMap((c) => c.items.map((i) => i.id));
}

module.exports = { makeNodeset, testDevice, itemIds, CNC_URI };
