"use strict";
// What node-opcua's loader does not keep of a device's NodeSet2: the
// namespace URIs and each node's nclink:Item extension (namespace
// urn:nclink:mapping), which names the NC-Link item a variable serves and how
// its value is encoded (lib/values.js). A small tag scanner, not a full XML
// parser: the document has already been accepted by node-opcua's loader; this
// only reads start tags, their attributes and the text of <Uri> elements.

const MAPPING_NS = "urn:nclink:mapping";

const ENTITIES = { amp: "&", lt: "<", gt: ">", quot: '"', apos: "'" };

function decode(text) {
  return text.replace(/&(#x[0-9a-fA-F]+|#[0-9]+|[a-z]+);/g, (m, e) => {
    if (e[0] === "#") {
      const code = e[1] === "x" ? parseInt(e.slice(2), 16) : parseInt(e.slice(1), 10);
      return Number.isFinite(code) ? String.fromCodePoint(code) : m;
    }
    return ENTITIES[e] !== undefined ? ENTITIES[e] : m;
  });
}

function attributesOf(text) {
  const out = {};
  const re = /([^\s=/>]+)\s*=\s*(?:"([^"]*)"|'([^']*)')/g;
  let m;
  while ((m = re.exec(text))) out[m[1]] = decode(m[2] !== undefined ? m[2] : m[3]);
  return out;
}

/// The string identifier of "ns=1;s=x_position" -> "x_position" (or undefined).
function stringIdOf(nodeId) {
  const m = /^(?:ns=\d+;)?s=(.*)$/s.exec(nodeId || "");
  return m ? m[1] : undefined;
}

/// -> {namespaceUris: [..], items: Map<itemId, {id, nodeId, stringId, encoding,
///     datatype, setable, type}>, withValue: Set<nodeId>} where nodeId is as
/// written in the file and withValue holds the variables that have a <Value>
/// (a fixed value from the model).
function scanNodeset(xml) {
  const text = xml.replace(/<!--[\s\S]*?-->/g, "").replace(/<!\[CDATA\[[\s\S]*?\]\]>/g, "");
  const namespaceUris = [];
  const items = new Map();
  const withValue = new Set();
  const tag = /<(\/?)([A-Za-z_][\w.\-]*(?::[A-Za-z_][\w.\-]*)?)([^>]*?)(\/?)>/g;
  let inNamespaceUris = false;
  let uriStart = -1;
  let current = null; // the UAVariable/UAObject being read
  const prefixes = [{}]; // xmlns prefix maps, innermost last
  let m;
  while ((m = tag.exec(text))) {
    const [, closing, name, rest, selfClosing] = m;
    const local = name.includes(":") ? name.slice(name.indexOf(":") + 1) : name;
    const prefix = name.includes(":") ? name.slice(0, name.indexOf(":")) : "";
    if (closing) {
      if (local === "NamespaceUris") inNamespaceUris = false;
      if (local === "Uri" && inNamespaceUris && uriStart >= 0) {
        namespaceUris.push(decode(text.slice(uriStart, m.index).trim()));
        uriStart = -1;
      }
      if (current && name === current.tag) current = null;
      if (prefixes.length > 1) prefixes.pop();
      continue;
    }
    const attrs = attributesOf(rest);
    const scope = { ...prefixes[prefixes.length - 1] };
    for (const [k, v] of Object.entries(attrs)) if (k.startsWith("xmlns:")) scope[k.slice(6)] = v;
    if (!selfClosing) prefixes.push(scope);

    if (local === "NamespaceUris") inNamespaceUris = !selfClosing;
    else if (local === "Uri" && inNamespaceUris) uriStart = selfClosing ? -1 : tag.lastIndex;
    else if (!prefix && /^UA(Variable|Object|Method|ObjectType|VariableType|DataType|ReferenceType|View)$/.test(local))
      current = selfClosing ? null : { tag: name, nodeId: attrs.NodeId, isVariable: local === "UAVariable", depth: prefixes.length };
    else if (local === "Value" && !prefix && current && current.isVariable && current.depth === prefixes.length - (selfClosing ? 0 : 1))
      withValue.add(current.nodeId);
    else if (local === "Item" && prefix && scope[prefix] === MAPPING_NS && current && current.isVariable && attrs.id) {
      items.set(attrs.id, {
        id: attrs.id,
        nodeId: current.nodeId,
        stringId: stringIdOf(current.nodeId),
        encoding: attrs.encoding || "scalar",
        datatype: attrs.datatype,
        setable: attrs.setable === "true",
        type: attrs.type,
      });
    }
  }
  return { namespaceUris, items, withValue };
}

module.exports = { scanNodeset, stringIdOf, MAPPING_NS };
