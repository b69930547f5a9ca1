"use strict";
// NC-Link JSON values <-> OPC UA Variants, per item, the way the mapping
// (GB/T 39561.3 appendix B, docs/opcua.md "Values") writes the item's
// variable: the `encoding` of its nclink:Item extension says how.
//   scalar      the JSON value in the variable's DataType (numeric strings
//               are numbers for numeric types; non-strings are text for String)
//   json        DataType String holding the JSON text (list, dict, objects)
//   enum_index  MultiStateDiscreteType: the NC-Link word's index in EnumStrings
//   two_state   TwoStateDiscreteType: Boolean; an item whose NC-Link values are
//               words has its true word in TrueState and false word in FalseState
// Pure: data type names are node-opcua's DataType names ("Double", ...), the
// server turns them into enum values. No value is ever guessed: what does not
// convert is an error the caller turns into a status code.

const INTEGER_RANGES = {
  SByte: [-128, 127],
  Byte: [0, 255],
  Int16: [-32768, 32767],
  UInt16: [0, 65535],
  Int32: [-2147483648, 2147483647],
  UInt32: [0, 4294967295],
  Int64: [Number.MIN_SAFE_INTEGER, Number.MAX_SAFE_INTEGER],
  UInt64: [0, Number.MAX_SAFE_INTEGER],
};

const FLOATS = new Set(["Double", "Float"]);

function numberOf(json) {
  if (typeof json === "number") return Number.isFinite(json) ? json : undefined;
  if (typeof json === "string" && json.trim() !== "") {
    const n = Number(json.trim());
    return Number.isFinite(n) ? n : undefined;
  }
  return undefined;
}

function jsonText(json) {
  return JSON.stringify(json);
}

/// One JSON scalar in `dataType` -> {value} or {error}.
function scalarToValue(json, dataType) {
  if (FLOATS.has(dataType)) {
    const n = numberOf(json);
    return n === undefined ? { error: `${jsonText(json)} is not a number` } : { value: n };
  }
  if (dataType in INTEGER_RANGES) {
    const n = numberOf(json);
    if (n === undefined || !Number.isInteger(n)) return { error: `${jsonText(json)} is not an integer` };
    const [lo, hi] = INTEGER_RANGES[dataType];
    if (n < lo || n > hi) return { error: `${n} is out of the ${dataType} range` };
    return { value: n };
  }
  switch (dataType) {
    case "Boolean":
      if (typeof json === "boolean") return { value: json };
      if (json === 0 || json === 1) return { value: json === 1 };
      if (typeof json === "string" && /^(true|false)$/i.test(json.trim())) return { value: json.trim().toLowerCase() === "true" };
      return { error: `${jsonText(json)} is not a Boolean` };
    case "String":
      if (typeof json === "string") return { value: json };
      if (typeof json === "number" || typeof json === "boolean") return { value: String(json) };
      return { value: jsonText(json) };
    case "DateTime": {
      const d = typeof json === "number" ? new Date(json) : typeof json === "string" ? new Date(json) : null;
      return d && !Number.isNaN(d.getTime()) ? { value: d } : { error: `${jsonText(json)} is not a time` };
    }
    default:
      return { error: `DataType ${dataType} is not served` };
  }
}

/// BaseDataType (the mapping's fallback for items it has no type for): the
/// Variant follows the JSON value.
function inferred(json) {
  if (typeof json === "number") return { dataType: "Double", value: json };
  if (typeof json === "boolean") return { dataType: "Boolean", value: json };
  if (typeof json === "string") return { dataType: "String", value: json };
  return { dataType: "String", value: jsonText(json) };
}

/// NC-Link JSON value of `meta`'s item -> {dataType, value, array?} or {error}.
/// null is {empty: true}: no value (the caller shows a Bad status).
function toVariant(json, meta) {
  if (json === null || json === undefined) return { empty: true };
  switch (meta.encoding) {
    case "json":
      if (meta.dataType !== "String") return { error: `json encoding needs DataType String, not ${meta.dataType}` };
      return { dataType: "String", value: jsonText(json) };
    case "enum_index": {
      const words = meta.enumStrings || [];
      let index = -1;
      if (typeof json === "string") index = words.indexOf(json.trim());
      else if (Number.isInteger(json) && json >= 0 && json < words.length) index = json;
      if (index < 0) return { error: `${jsonText(json)} is not one of ${jsonText(words)}` };
      return { dataType: meta.dataType, value: index };
    }
    case "two_state":
      if (typeof json === "string" && meta.trueState !== undefined && json.trim() === meta.trueState) return { dataType: "Boolean", value: true };
      if (typeof json === "string" && meta.falseState !== undefined && json.trim() === meta.falseState) return { dataType: "Boolean", value: false };
      break;
    default:
      break;
  }
  if (meta.dataType === "Variant" || meta.dataType === "Null") return inferred(json);
  if (meta.array) {
    if (!Array.isArray(json)) return { error: `${jsonText(json)} is not an array` };
    const values = [];
    for (const element of json) {
      const r = scalarToValue(element, meta.dataType);
      if (r.error) return { error: r.error };
      values.push(r.value);
    }
    return { dataType: meta.dataType, value: values, array: true };
  }
  const r = scalarToValue(json, meta.dataType);
  return r.error ? { error: r.error } : { dataType: meta.dataType, value: r.value };
}

function scalarToJson(value, dataType) {
  if (value === null || value === undefined) return { status: "BadTypeMismatch", reason: "no value" };
  if (FLOATS.has(dataType)) {
    if (!Number.isFinite(value)) return { status: "BadOutOfRange", reason: `${value} has no JSON form` };
    return { json: value };
  }
  if (dataType in INTEGER_RANGES) {
    // node-opcua carries 64-bit integers as [high, low] words.
    if (Array.isArray(value)) value = value[0] * 4294967296 + value[1];
    if (!Number.isSafeInteger(value)) return { status: "BadOutOfRange", reason: `${value} has no exact JSON form` };
    return { json: value };
  }
  switch (dataType) {
    case "Boolean":
    case "String":
      return { json: value };
    case "DateTime":
      return { json: value.getTime() };
    default:
      return { status: "BadTypeMismatch", reason: `DataType ${dataType} is not written` };
  }
}

/// An OPC UA write {dataType, value, array} to `meta`'s item -> {json} or
/// {status, reason} (status a node-opcua StatusCodes name).
/// `wordsSeen`: the item's NC-Link values are words (two_state), learnt from
/// the stream; a Boolean is then written as the true or false word.
function fromVariant(variant, meta, { wordsSeen = false } = {}) {
  const { dataType, value } = variant;
  switch (meta.encoding) {
    case "json": {
      if (dataType !== "String" || typeof value !== "string") return { status: "BadTypeMismatch", reason: "a JSON text (String) is expected" };
      try {
        return { json: JSON.parse(value) };
      } catch {
        return { status: "BadTypeMismatch", reason: "the String is not JSON text" };
      }
    }
    case "enum_index": {
      const words = meta.enumStrings || [];
      if (!Number.isInteger(value)) return { status: "BadTypeMismatch", reason: "an EnumStrings index is expected" };
      if (value < 0 || value >= words.length) return { status: "BadOutOfRange", reason: `index ${value} is outside EnumStrings (${words.length})` };
      return { json: words[value] };
    }
    case "two_state":
      if (dataType !== "Boolean") return { status: "BadTypeMismatch", reason: "a Boolean is expected" };
      if (wordsSeen && meta.trueState !== undefined && meta.falseState !== undefined)
        return { json: value ? meta.trueState : meta.falseState };
      return { json: value };
    default:
      break;
  }
  if (variant.array) {
    const out = [];
    for (const element of value) {
      const r = scalarToJson(element, dataType);
      if (r.status) return r;
      out.push(r.json);
    }
    return { json: out };
  }
  return scalarToJson(value, dataType);
}

module.exports = { toVariant, fromVariant };
