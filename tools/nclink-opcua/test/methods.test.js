"use strict";
// The model's METHOD configs as OPC UA Methods on the device object, called
// through a fake bridge's /call (docs/opcua.md "Methods"), seen through a
// node-opcua client: browse, arguments, a call answered at its result, a
// refused call's status, a bridge that does not answer.
const { describe, it, before, after } = require("node:test");
const assert = require("node:assert/strict");

const opcua = require("../lib/node-opcua");
const { FakeBridge } = require("./support/fake-bridge");
const { makeNodeset, testDevice } = require("./support/fake-nodeset");
const { freePort, startServer, connect } = require("./support/harness");

const { DataType, StatusCodes, Variant, NodeClass } = opcua;
const DEV = "fake-mill-1";
const URI = `urn:nclink:device:${DEV}`;

// Methods as the simulated mill's model declares them (models/sim-mill.json):
// root configs (every device offers them), args as an object, as an array of
// names and objects, and absent.
const MODEL = {
  id: "root",
  type: "NC_LINK_ROOT",
  version: "1.0",
  configs: [
    { id: "cycle_start", name: "Cycle start", type: "METHOD", description: "Start the loaded program", args: {} },
    {
      id: "program_transfer",
      name: "Program transfer",
      type: "METHOD",
      args: [
        { name: "operation", default: "push", description: "push or pull" },
        { name: "source", description: "a local file path or a program name" },
        { name: "destination", optional: true },
      ],
    },
    { id: "set_offset", type: "METHOD", args: { tool: "T1", length: 12.5 } },
    { id: "free_form", type: "METHOD" },
    { id: "not_a_method", type: "VERSION", value: "1" },
  ],
  devices: [{ id: "mill", guid: DEV, type: "MACHINE", configs: [{ id: "home_axes", type: "METHOD", args: ["axis"] }] }],
};

describe("nclink-opcua methods", () => {
  let bridge;
  let server;
  let c;
  let ns;
  const deviceId = () => `ns=${ns};s=${DEV}`;
  const methodId = (id) => `ns=${ns};s=${DEV}.Method.${id}`;
  const call = (id, inputs) =>
    c.session.call({ objectId: deviceId(), methodId: methodId(id), inputArguments: inputs.map((v) => new Variant({ dataType: DataType.String, value: v })) });

  before(async () => {
    opcua.debug.setWarningLogger(() => {});
    bridge = new FakeBridge({ pingMs: 300 });
    bridge.addDevice({ dev: DEV, name: "Fake mill", version: "1", nodeset: makeNodeset(testDevice(DEV)), values: { x_position: 1 }, model: MODEL });
    await bridge.start();
    const port = await freePort();
    server = startServer(["--bridge", bridge.url, "--port", String(port), "--reconnect-max", "500", "--call-timeout", "3000"]);
    // A loaded machine takes long to load node-opcua.
    const serving = await server.waitForLine(/device fake-mill-1: serving \d+ items/, { ms: 240000 });
    assert.match(serving, /\(\d+ writable\), 5 methods,/, server.lines.join("\n"));
    c = await connect(opcua, `opc.tcp://127.0.0.1:${port}`);
    ns = (await c.session.readNamespaceArray()).indexOf(URI);
    assert.ok(ns > 0);
  });

  after(async () => {
    if (c) await c.close().catch(() => {});
    if (server) assert.equal((await server.stop()).code, 0);
    if (bridge) await bridge.stop();
  });

  it("offers every METHOD config of the root and the device as a Method on the device object", async () => {
    const browsed = await c.session.browse({ nodeId: deviceId(), referenceTypeId: "HasComponent", includeSubtypes: true, browseDirection: 0, resultMask: 63 });
    const methods = browsed.references.filter((r) => r.nodeClass === NodeClass.Method).map((r) => r.browseName.name).sort();
    assert.deepEqual(methods, ["cycle_start", "free_form", "home_axes", "program_transfer", "set_offset"]);
  });

  it("gives each Method the model's args as String InputArguments, and Result and Return outputs", async () => {
    const property = async (id, name) => {
      const browsed = await c.session.browse({ nodeId: methodId(id), referenceTypeId: "HasProperty", includeSubtypes: true, browseDirection: 0, resultMask: 63 });
      const ref = browsed.references.find((r) => r.browseName.name === name);
      if (!ref) return [];
      const dv = await c.session.read({ nodeId: ref.nodeId, attributeId: opcua.AttributeIds.Value });
      return dv.value.value;
    };
    const argsOf = async (id) => (await property(id, "InputArguments")).map((a) => [a.name, a.dataType.value]);
    assert.deepEqual(await argsOf("cycle_start"), []);
    assert.deepEqual(await argsOf("program_transfer"), [["operation", DataType.String], ["source", DataType.String], ["destination", DataType.String]]);
    assert.deepEqual(await argsOf("set_offset"), [["tool", DataType.String], ["length", DataType.String]]);
    assert.deepEqual(await argsOf("home_axes"), [["axis", DataType.String]]);
    assert.deepEqual(await argsOf("free_form"), [["args", DataType.String]]);
    assert.deepEqual((await property("cycle_start", "OutputArguments")).map((a) => [a.name, a.dataType.value]), [["Result", DataType.String], ["Return", DataType.String]]);
  });

  it("a call runs NC-Link Method/Call through the bridge and answers at its result", async () => {
    bridge.callAnswer = (dev, method) => ({ code: "OK", result: "finished", return: { started: method } });
    const before = bridge.calls.length;
    const r = await call("cycle_start", []);
    assert.equal(r.statusCode.name, "Good");
    assert.deepEqual(bridge.calls.slice(before), [{ dev: DEV, method: "cycle_start", args: {}, timeoutMs: 3000 }]);
    assert.equal(r.outputArguments[0].value, "finished");
    assert.deepEqual(JSON.parse(r.outputArguments[1].value), { started: "cycle_start" });
  });

  it("passes the arguments by name, an empty optional one left out for the adapter's default", async () => {
    bridge.callAnswer = () => ({ code: "OK", result: "finished" });
    const before = bridge.calls.length;
    const r = await call("program_transfer", ["", "/tmp/o1000.nc", ""]);
    assert.equal(r.statusCode.name, "Good");
    assert.equal(r.outputArguments[1].value, "", "nothing returned: empty Return");
    assert.deepEqual(bridge.calls[before].args, { source: "/tmp/o1000.nc" });
    await call("free_form", ['{"speed": 3}']);
    assert.deepEqual(bridge.calls[before + 1].args, { speed: 3 });
    const bad = await call("free_form", ["[1,2]"]);
    assert.equal(bad.statusCode.name, "BadInvalidArgument");
    assert.equal(bridge.calls.length, before + 2, "a malformed args text is not sent");
  });

  it("a canceled run is Good with Result canceled", async () => {
    bridge.callAnswer = () => ({ code: "OK", result: "canceled" });
    const r = await call("cycle_start", []);
    assert.equal(r.statusCode.name, "Good");
    assert.equal(r.outputArguments[0].value, "canceled");
  });

  it("a refused call gets the status of its table-19 code", async () => {
    for (const [error, reason, status] of [
      [401, "Node not exists", "BadMethodInvalid"],
      [102, "Parameter Missing", "BadArgumentsMissing"],
      [409, "arguments nimiety", "BadTooManyArguments"],
      [417, "Insufficient method resources", "BadResourceUnavailable"],
      [301, "Permission Denied", "BadUserAccessDenied"],
      [203, "Timeout", "BadTimeout"],
      [202, "DEV_UNREACHABLE", "BadCommunicationError"],
      [999, "something else", "BadUnexpectedError"],
    ]) {
      bridge.callAnswer = () => ({ code: "NG", result: "error", error, reason });
      const r = await call("cycle_start", []);
      assert.equal(r.statusCode.name, status, `${error} ${reason}`);
    }
  });

  it("a bridge that does not answer in time is BadTimeout, and the server keeps serving", async () => {
    bridge.callAnswer = () => new Promise((resolve) => setTimeout(() => resolve({ code: "OK", result: "finished" }), 9000));
    const r = await call("cycle_start", []);
    assert.equal(r.statusCode.name, "BadTimeout");
    bridge.callAnswer = () => ({ code: "OK", result: "finished" });
    assert.equal((await call("cycle_start", [])).statusCode.name, "Good");
    assert.ok(StatusCodes.Good);
  });
});
