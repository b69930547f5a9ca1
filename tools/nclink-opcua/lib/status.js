"use strict";
// Which OPC UA StatusCode a client sees (docs/opcua.md "Status codes").
// Names are node-opcua StatusCodes names; the tables are the documentation.

/// NG answers to a Set (GB/T 41970 table 19) -> the Write result. `reason`
/// DEV_UNREACHABLE (the agent's answer for an offline adapter, 8.3.4/8.3.5)
/// wins over its error number, which agents fill differently.
const SET_ERRORS = new Map([
  [101, "BadOutOfRange"], // Out of Range: array/list index out of range
  [102, "BadInvalidArgument"], // Parameter Missing
  [202, "BadCommunicationError"], // Unavailable: the data or the adapter cannot be reached
  [203, "BadTimeout"], // Timeout
  [301, "BadUserAccessDenied"], // Permission Denied: the agent or adapter refused this application
  [401, "BadNodeIdUnknown"], // Node not exists: the adapter does not know the item (model changed)
  [402, "BadInvalidArgument"], // No index passed in
  [403, "BadInvalidArgument"], // No key passed in
  [404, "BadOutOfMemory"], // Memory configured error
  [405, "BadTypeMismatch"], // Value type error
  [409, "BadInvalidArgument"], // arguments nimiety
  [410, "BadTypeMismatch"], // key error (dict key of the wrong type)
  [411, "BadInvalidArgument"], // Attribute error
  [412, "BadInvalidArgument"], // syntax error
  [413, "BadInvalidArgument"], // keys of arguments error
]);

function setAnswerStatus(answer) {
  if (answer.code === "OK") return "Good";
  if (typeof answer.reason === "string" && answer.reason.toUpperCase() === "DEV_UNREACHABLE") return "BadCommunicationError";
  const code = Number(answer.error);
  return SET_ERRORS.get(code) || "BadUnexpectedError";
}

/// A Set that got no NG/OK answer (lib/bridge-client.js BridgeError kinds).
function setFailureStatus(kind) {
  return kind === "timeout" ? "BadTimeout" : "BadCommunicationError";
}

/// The status of an item's value, most important cause first.
///   link: {bridgeUp, state ("online"|"offline"|"unknown"), live (snapshot seen)}
///   item: {hasValue, quality ("good"|"bad"), empty (null), convertible}
function itemStatus(link, item) {
  if (!link.bridgeUp) return "BadCommunicationError"; // the stream to the bridge is down
  if (link.state === "offline") return "BadNoCommunication"; // the device's adapter is offline
  if (!link.live || link.state !== "online") return "BadWaitingForInitialData"; // state unknown / no snapshot yet
  if (!item.hasValue) return "BadWaitingForInitialData";
  if (item.quality === "bad" || item.empty) return "BadDeviceFailure"; // the adapter could not read it
  if (!item.convertible) return "BadConfigurationError"; // the value does not fit the model's DataType
  return "Good";
}

module.exports = { setAnswerStatus, setFailureStatus, itemStatus, SET_ERRORS };
