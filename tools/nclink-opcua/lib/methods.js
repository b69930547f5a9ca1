"use strict";
// The NC-Link METHOD configs of a device as OPC UA Methods on its device
// object (GB/T 39561.3 B.5 e): operations are methods). A call runs NC-Link
// Method/Call through the bridge (POST /nclink/v1/devices/{dev}/call) and is
// answered when the machine's Method/Result comes, within the call timeout
// (docs/opcua.md "Methods"). Everything here runs on the event loop thread.

/// The METHOD configs that apply to device `dev` of an NC-Link model (the
/// bridge's /model): the root's configs, which every device of the model
/// offers (docs/methods.md), then the device's own. -> [{id, name, description, args}]
function methodsOf(model, dev) {
  const out = [];
  const seen = new Set();
  const take = (configs) => {
    for (const c of Array.isArray(configs) ? configs : []) {
      if (!c || c.type !== "METHOD" || typeof c.id !== "string" || c.id === "" || seen.has(c.id)) continue;
      seen.add(c.id);
      out.push({ id: c.id, name: typeof c.name === "string" && c.name ? c.name : c.id, description: typeof c.description === "string" ? c.description : "", args: argsOf(c.args) });
    }
  };
  if (!model || typeof model !== "object") return out;
  take(model.configs);
  const devices = Array.isArray(model.devices) ? model.devices : [];
  const device = devices.find((d) => d && d.guid === dev) || (devices.length === 1 ? devices[0] : null);
  if (device) take(device.configs);
  return out;
}

/// A METHOD's `args` (table 6; docs/methods.md "How the METHOD object
/// declares its args") as the input arguments: [{name, description, optional}],
/// or null when nothing is declared (any args object goes: one input "args").
function argsOf(args) {
  if (args === undefined || args === null) return null;
  if (Array.isArray(args)) {
    const out = [];
    for (const a of args) {
      if (typeof a === "string" && a !== "") out.push({ name: a, description: "", optional: false });
      else if (a && typeof a === "object" && typeof a.name === "string" && a.name !== "")
        out.push({ name: a.name, description: typeof a.description === "string" ? a.description : "", optional: a.optional === true || a.default !== undefined });
    }
    return out;
  }
  if (typeof args === "object") {
    // Every key is a parameter the call must give; the value is an example.
    return Object.keys(args).map((name) => ({ name, description: `e.g. ${JSON.stringify(args[name])}`, optional: false }));
  }
  return null;
}

/// The args object of a call from the OPC UA input strings: an empty string
/// for an optional argument leaves it out (the adapter fills its default);
/// without declared args the one input is a JSON object text ("" = none).
/// -> {args} or {status, reason}
function callArgs(declared, inputs) {
  const texts = inputs.map((v) => (v && typeof v.value === "string" ? v.value : ""));
  if (declared === null) {
    const text = texts[0] || "";
    if (text.trim() === "") return { args: {} };
    try {
      const parsed = JSON.parse(text);
      if (parsed && typeof parsed === "object" && !Array.isArray(parsed)) return { args: parsed };
    } catch {
      // below
    }
    return { status: "BadInvalidArgument", reason: `"args" must be a JSON object, not ${JSON.stringify(text.slice(0, 80))}` };
  }
  const args = {};
  declared.forEach((a, i) => {
    if (texts[i] === "" && a.optional) return;
    args[a.name] = texts[i];
  });
  return { args };
}

/// NG answers to a Method/Call (GB/T 41970 table 19; docs/methods.md
/// "Validation of a call") -> the Call result.
const CALL_ERRORS = new Map([
  [102, "BadArgumentsMissing"], // Parameter Missing: a declared arg missing
  [202, "BadCommunicationError"], // Unavailable
  [203, "BadTimeout"], // Timeout: no Method/Result in time
  [301, "BadUserAccessDenied"], // Permission Denied (also a driver's refusal)
  [401, "BadMethodInvalid"], // Node not exists: the adapter has no such METHOD (model changed)
  [405, "BadTypeMismatch"], // Value type error
  [409, "BadTooManyArguments"], // arguments nimiety: an arg the METHOD does not declare
  [412, "BadInvalidArgument"], // syntax error
  [417, "BadResourceUnavailable"], // Insufficient method resources: methods.max_running under way
]);

/// A Method/Result (the bridge's answer) -> status name. finished and
/// canceled are Good (the Result output says which); error is its code's.
function callAnswerStatus(answer) {
  if (answer.code === "OK") return "Good";
  if (typeof answer.reason === "string" && answer.reason.toUpperCase() === "DEV_UNREACHABLE") return "BadCommunicationError";
  return CALL_ERRORS.get(Number(answer.error)) || "BadUnexpectedError";
}

/// Adds the methods to the device object `deviceNode` in namespace `namespace`
/// and binds each to `call(dev, methodId, args)` -> Promise<answer> (rejects
/// with a BridgeError). -> the UAMethod nodes.
function addMethods({ opcua, namespace, deviceNode, dev, methods, call, log }) {
  const { DataType, StatusCodes, Variant } = opcua;
  const added = [];
  for (const m of methods) {
    const inputs = m.args === null
      ? [{ name: "args", dataType: DataType.String, description: { text: "the call's args as a JSON object (empty: none)" } }]
      : m.args.map((a) => ({ name: a.name, dataType: DataType.String, description: { text: `${a.description}${a.optional ? " (optional: empty leaves it out)" : ""}`.trim() } }));
    const method = namespace.addMethod(deviceNode, {
      nodeId: `s=${dev}.Method.${m.id}`,
      browseName: m.id,
      displayName: m.name,
      description: m.description,
      inputArguments: inputs,
      outputArguments: [
        { name: "Result", dataType: DataType.String, description: { text: "finished or canceled (NC-Link Method/Result)" } },
        { name: "Return", dataType: DataType.String, description: { text: "what the method returned, as JSON (empty when nothing)" } },
      ],
    });
    const run = async (inputArguments) => {
      const prepared = callArgs(m.args, inputArguments || []);
      if (prepared.status) {
        log.info(`call ${dev}/${m.id}: refused, ${prepared.reason} (${prepared.status})`);
        return { statusCode: StatusCodes[prepared.status] };
      }
      let answer;
      try {
        answer = await call(dev, m.id, prepared.args);
      } catch (e) {
        const status = e.kind === "timeout" ? "BadTimeout" : "BadCommunicationError";
        log.warn(`call ${dev}/${m.id}: no answer from the bridge, ${e.message} (${status})`);
        return { statusCode: StatusCodes[status] };
      }
      const status = callAnswerStatus(answer);
      if (status !== "Good") {
        log.info(`call ${dev}/${m.id}: ${answer.result || "error"} NG ${answer.error} ${answer.reason || ""} (${status})`);
        return { statusCode: StatusCodes[status] };
      }
      const returned = answer.return === undefined || answer.return === null ? "" : JSON.stringify(answer.return);
      log.info(`call ${dev}/${m.id}: ${answer.result}`);
      return {
        statusCode: StatusCodes.Good,
        outputArguments: [
          new Variant({ dataType: DataType.String, value: String(answer.result || "finished") }),
          new Variant({ dataType: DataType.String, value: returned }),
        ],
      };
    };
    // node-opcua takes the callback form (three parameters).
    method.bindMethod(function (inputArguments, context, callback) {
      run(inputArguments).then(
        (result) => callback(null, result),
        (e) => {
          log.error(`call ${dev}/${m.id}: internal error: ${e && e.stack ? e.stack : e}`);
          callback(null, { statusCode: StatusCodes.BadInternalError });
        },
      );
    });
    added.push(method);
  }
  return added;
}

module.exports = { methodsOf, argsOf, callArgs, callAnswerStatus, addMethods, CALL_ERRORS };
