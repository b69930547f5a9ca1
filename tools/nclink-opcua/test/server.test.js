"use strict";
// nclink-opcua against a fake bridge that follows the contract, seen through
// node-opcua clients: browse, read, subscribe, write, security, users, the
// device and the bridge coming and going, a model change.
const { describe, it, before, after } = require("node:test");
const assert = require("node:assert/strict");
const fs = require("node:fs");
const path = require("node:path");

const opcua = require("../lib/node-opcua");
const { FakeBridge } = require("./support/fake-bridge");
const { makeNodeset, testDevice, itemIds } = require("./support/fake-nodeset");
const { tempDir, freePort, waitUntil, startServer, connect, browseVariables } = require("./support/harness");

const { AttributeIds, DataType, StatusCodes, MessageSecurityMode, SecurityPolicy, UserTokenType, OPCUACertificateManager } = opcua;
const DEV = "fake-mill-1";
const URI = `urn:nclink:device:${DEV}`;

const INITIAL = {
  x_position: 12.5,
  spindle_override: 100,
  spindle_mode: "stop",
  status: "running",
  work_mode: "auto",
  door_closed: true,
  tool_number: 3,
  program: "O1000",
  parameters: { feed_max: 5000, name: "mill" },
  warning: {},
};
// What a client reads for each INITIAL value (lib/values.js, per encoding).
const EXPECTED = {
  x_position: [DataType.Double, 12.5],
  spindle_override: [DataType.Double, 100],
  spindle_mode: [DataType.UInt32, 1],
  status: [DataType.UInt32, 0],
  work_mode: [DataType.Boolean, true],
  door_closed: [DataType.Boolean, true],
  tool_number: [DataType.Int32, 3],
  program: [DataType.String, "O1000"],
  parameters: [DataType.String, '{"feed_max":5000,"name":"mill"}'],
  warning: [DataType.String, "{}"],
  spindle_max_speed: [DataType.Double, 12000], // fixed in the nodeset, not streamed
};

const SETTLE_MS = 20000;

function quiet() {
  // The clients in this process log through node-opcua-debug too.
  opcua.debug.setWarningLogger(() => {});
}

describe("nclink-opcua against a fake bridge", () => {
  let bridge;
  let server;
  let port;
  let url;
  let pki;
  let knownClientPki;
  let c; // anonymous, security None
  let ns;
  const nodeId = (id) => `ns=${ns};s=${id}`;
  const read = (id, session = c.session) => session.read({ nodeId: nodeId(id), attributeId: AttributeIds.Value });
  const write = (id, dataType, value, session = c.session) =>
    session.write({ nodeId: nodeId(id), attributeId: AttributeIds.Value, value: { value: { dataType, value } } });
  const statusOf = async (id) => (await read(id)).statusCode.name;
  const waitStatus = (id, name) => waitUntil(async () => (await statusOf(id)) === name, { ms: SETTLE_MS, what: `${id} ${name}` });

  before(async () => {
    quiet();
    bridge = new FakeBridge({ pingMs: 300 });
    bridge.addDevice({ dev: DEV, name: "Fake mill", version: "1", nodeset: makeNodeset(testDevice(DEV)), values: INITIAL });
    await bridge.start();
    port = await freePort();
    url = `opc.tcp://127.0.0.1:${port}`;
    pki = tempDir("nclink-opcua-pki-");
    // A client certificate the administrator trusts before the server starts
    // (put into <pki>/trusted/certs/; node-opcua reads the folder when it opens it).
    knownClientPki = tempDir("nclink-opcua-client-pki-");
    const cm = new OPCUACertificateManager({ rootFolder: knownClientPki, automaticallyAcceptUnknownCertificate: false });
    await cm.initialize();
    const maker = opcua.OPCUAClient.create({ applicationName: "nclink-opcua-test", clientCertificateManager: cm });
    await maker.createDefaultCertificate();
    fs.mkdirSync(path.join(pki, "trusted", "certs"), { recursive: true });
    fs.copyFileSync(maker.certificateFile, path.join(pki, "trusted", "certs", "known-client.pem"));
    await cm.dispose();
    server = startServer([
      "--bridge", bridge.url, "--port", String(port), "--pki", pki,
      "--user", "operator:right-password", "--reconnect-max", "500", "--stream-idle", "3000",
    ]);
    await server.waitForLine(/device fake-mill-1: serving 11 items \(6 writable\)/);
    c = await connect(opcua, url);
    ns = (await c.session.readNamespaceArray()).indexOf(URI);
    assert.ok(ns > 0, `namespace ${URI} is served`);
  });

  after(async () => {
    if (c) await c.close().catch(() => {});
    if (server) {
      const r = await server.stop();
      assert.equal(r.code, 0, "SIGTERM stops it cleanly");
    }
    if (bridge) await bridge.stop();
    if (pki) fs.rmSync(pki, { recursive: true, force: true });
    if (knownClientPki) fs.rmSync(knownClientPki, { recursive: true, force: true });
  });

  it("serves one namespace per device, the device object under Objects", async () => {
    const objects = await c.session.browse("i=85");
    const device = objects.references.find((r) => r.nodeId.namespace === ns);
    assert.ok(device, "device object organized by Objects");
    assert.equal(device.nodeId.value, DEV);
    assert.equal(device.browseName.name, "Fake mill");
    assert.equal(bridge.nodesetRequests[0].profile, "basic");
  });

  it("browsing finds every item", async () => {
    const found = await browseVariables(opcua, c.session, "i=85", ns);
    for (const id of itemIds(testDevice(DEV))) assert.ok(found.has(id), `item ${id} browsed`);
    assert.ok(found.has("x_position.EngineeringUnits"), "properties are there too");
    assert.ok(found.has("spindle_mode.EnumStrings"));
  });

  it("reads what the stream sent, in the model's DataType, with the source time", async () => {
    for (const [id, [dataType, value]] of Object.entries(EXPECTED)) {
      const dv = await read(id);
      assert.equal(dv.statusCode.name, "Good", id);
      assert.equal(dv.value.dataType, dataType, id);
      assert.deepEqual(dv.value.value, value, id);
    }
    const sent = bridge.devices.get(DEV).values.get("x_position").time;
    assert.equal((await read("x_position")).sourceTimestamp.getTime(), sent);
    assert.equal((await read(`${DEV}.Availability`)).value.value, "AVAILABLE");
  });

  it("a streamed value reaches reads and subscriptions", async () => {
    const subscription = await c.session.createSubscription2({ requestedPublishingInterval: 50, publishingEnabled: true, requestedMaxKeepAliveCount: 20, requestedLifetimeCount: 100 });
    const seen = [];
    const item = await subscription.monitor({ nodeId: nodeId("x_position"), attributeId: AttributeIds.Value }, { samplingInterval: 0, queueSize: 100, discardOldest: true }, 0);
    item.on("changed", (dv) => seen.push(dv.value.value));
    const time = Date.now() - 5;
    bridge.pushValue(DEV, "x_position", 42.25, { time });
    await waitUntil(() => seen.includes(42.25), { ms: SETTLE_MS, what: "data change notification" });
    const dv = await read("x_position");
    assert.equal(dv.value.value, 42.25);
    assert.equal(dv.sourceTimestamp.getTime(), time);
    bridge.pushValue(DEV, "status", "holding");
    await waitUntil(async () => (await read("status")).value.value === 2, { what: "status holding = 2" });
    await subscription.terminate();
  });

  it("a write to a setable item becomes the bridge's Set with the NC-Link value", async () => {
    const cases = [
      ["spindle_override", DataType.Double, 80, 80],
      ["tool_number", DataType.Int32, 7, 7],
      ["program", DataType.String, "O2000", "O2000"],
      ["spindle_mode", DataType.UInt32, 2, "reverse"],
      ["work_mode", DataType.Boolean, false, "manual"], // its NC-Link values are words
      ["parameters", DataType.String, '{"feed_max":4000}', { feed_max: 4000 }],
    ];
    for (const [id, dataType, value, json] of cases) {
      const before = bridge.sets.length;
      const status = await write(id, dataType, value);
      assert.equal(status.name, "Good", id);
      assert.deepEqual(bridge.sets.slice(before), [{ dev: DEV, id, value: json }], id);
      assert.deepEqual((await read(id)).value.value, value, `${id} reads back`);
    }
  });

  it("a write to a read-only item is BadNotWritable and never reaches the bridge", async () => {
    const before = bridge.sets.length;
    assert.equal((await write("x_position", DataType.Double, 1)).name, "BadNotWritable");
    assert.equal((await write("status", DataType.UInt32, 1)).name, "BadNotWritable");
    assert.equal(bridge.sets.length, before);
  });

  it("a write that does not convert is refused before the bridge", async () => {
    const before = bridge.sets.length;
    assert.equal((await write("spindle_override", DataType.String, "fast")).name, "BadTypeMismatch");
    assert.equal((await write("spindle_mode", DataType.UInt32, 9)).name, "BadOutOfRange");
    assert.equal((await write("parameters", DataType.String, "{not json")).name, "BadTypeMismatch");
    assert.equal(bridge.sets.length, before);
  });

  it("a write of part of a value, or with a status, is BadWriteNotSupported and never reaches the bridge", async () => {
    const before = bridge.sets.length;
    const partial = await c.session.write({ nodeId: nodeId("program"), attributeId: AttributeIds.Value, indexRange: "0:1", value: { value: { dataType: DataType.String, value: "XY" } } });
    assert.equal(partial.name, "BadWriteNotSupported");
    const withStatus = await c.session.write({ nodeId: nodeId("program"), attributeId: AttributeIds.Value, value: { value: { dataType: DataType.String, value: "O9" }, statusCode: StatusCodes.Bad } });
    assert.equal(withStatus.name, "BadWriteNotSupported");
    assert.equal(bridge.sets.length, before);
  });

  it("an NG from the bridge maps to the documented status and keeps the old value", async () => {
    const answers = [
      [{ code: "NG", error: 301, reason: "Permission Denied" }, "BadUserAccessDenied"],
      [{ code: "NG", error: 101, reason: "Out of Range" }, "BadOutOfRange"],
      [{ code: "NG", error: 405, reason: "Value type error" }, "BadTypeMismatch"],
      [{ code: "NG", error: 203, reason: "Timeout" }, "BadTimeout"],
      [{ code: "NG", error: 202, reason: "DEV_UNREACHABLE" }, "BadCommunicationError"],
    ];
    const old = (await read("spindle_override")).value.value;
    try {
      for (const [answer, status] of answers) {
        bridge.setAnswer = () => answer;
        assert.equal((await write("spindle_override", DataType.Double, 55)).name, status, JSON.stringify(answer));
        const dv = await read("spindle_override");
        assert.equal(dv.statusCode.name, "Good");
        assert.equal(dv.value.value, old);
      }
    } finally {
      bridge.setAnswer = () => ({ code: "OK" });
    }
  });

  it("a value of bad quality is BadDeviceFailure, good again with the next value", async () => {
    bridge.pushValue(DEV, "tool_number", null, { quality: "bad" });
    await waitStatus("tool_number", "BadDeviceFailure");
    assert.equal((await statusOf("x_position")), "Good", "other items are not affected");
    bridge.pushValue(DEV, "tool_number", 4);
    await waitStatus("tool_number", "Good");
    assert.equal((await read("tool_number")).value.value, 4);
  });

  it("a value that does not fit the model is BadConfigurationError, logged once", async () => {
    const from = server.lines.length;
    bridge.pushValue(DEV, "status", "sideways");
    await waitStatus("status", "BadConfigurationError");
    bridge.pushValue(DEV, "status", "free");
    await waitStatus("status", "Good");
    assert.equal((await read("status")).value.value, 1);
    assert.equal(server.lines.slice(from).filter((l) => /item status: value "sideways" does not convert/.test(l)).length, 1);
  });

  it("the device going offline turns its values Bad, back Good when online", async () => {
    bridge.setState(DEV, "offline");
    await waitStatus("x_position", "BadNoCommunication");
    for (const id of Object.keys(EXPECTED)) assert.equal(await statusOf(id), "BadNoCommunication", id);
    assert.equal((await read(`${DEV}.Availability`)).value.value, "UNAVAILABLE");
    bridge.setState(DEV, "online");
    await waitStatus("x_position", "Good");
    assert.equal((await read("x_position")).value.value, 42.25);
    assert.equal((await read(`${DEV}.Availability`)).value.value, "AVAILABLE");
  });

  it("the stream dropping is survived: reconnect, snapshot, Good again", async () => {
    const from = server.lines.length;
    bridge.dropStreams();
    await server.waitForLine(/bridge stream lost/, { from });
    await server.waitForLine(/bridge stream open/, { from });
    await waitStatus("x_position", "Good");
  });

  it("the bridge disappearing makes every value BadCommunicationError until it is back", async () => {
    const from = server.lines.length;
    await bridge.stop();
    await server.waitForLine(/bridge stream lost/, { from });
    await waitStatus("x_position", "BadCommunicationError");
    for (const id of Object.keys(EXPECTED)) assert.equal(await statusOf(id), "BadCommunicationError", id);
    // A write while the bridge is gone: no answer to give, the status says why.
    assert.equal((await write("spindle_override", DataType.Double, 90)).name, "BadCommunicationError");
    bridge.devices.get(DEV).values.get("x_position").value = -3.5; // changed while we were away
    await bridge.start(bridge.port);
    await server.waitForLine(/bridge stream open/, { from });
    await waitStatus("x_position", "Good");
    assert.equal((await read("x_position")).value.value, -3.5, "the snapshot after reconnect is served");
  });

  it("a device that appears later is added to the running server once its model is known", async () => {
    const from = server.lines.length;
    const dev = "fake-mill-2";
    // Announced before the bridge has its model: the nodeset is 404 for now.
    bridge.addDevice({ dev, name: "Second mill", version: "", nodeset: undefined });
    bridge.setState(dev, "online");
    await server.waitForLine(/device fake-mill-2: nodeset \(version \) not fetched: .*HTTP 404/, { from });
    bridge.changeModel(dev, makeNodeset(testDevice(dev)), "1");
    await server.waitForLine(/device fake-mill-2: serving 11 items/, { from });
    bridge.pushValue(dev, "x_position", 7.5);
    // Same session: a new device needs no restart.
    // The Server's NamespaceArray (i=2255) grew (the client's readNamespaceArray caches).
    const namespaces = (await c.session.read({ nodeId: "i=2255", attributeId: AttributeIds.Value })).value.value;
    const ns2 = namespaces.indexOf(`urn:nclink:device:${dev}`);
    assert.ok(ns2 > ns, "the new device has a namespace of its own");
    await waitUntil(async () => {
      const dv = await c.session.read({ nodeId: `ns=${ns2};s=x_position`, attributeId: AttributeIds.Value });
      return dv.statusCode.name === "Good" && dv.value.value === 7.5;
    }, { what: "the second device's value" });
    assert.equal(await statusOf("x_position"), "Good", "the first device carries on");
    assert.ok(!server.lines.slice(from).some((l) => /restarting/.test(l)));
  });

  it("Basic256Sha256 SignAndEncrypt: an unknown client is rejected, a trusted one gets in", async () => {
    const serverCert = path.join(pki, "own", "certs", "certificate.pem");
    assert.ok(fs.existsSync(serverCert), "the server made its certificate in --pki");
    // A client trusts the server's certificate: it is in the client's store
    // before the store is opened (it is read when opened).
    const secureClient = async (dir) => {
      fs.mkdirSync(path.join(dir, "trusted", "certs"), { recursive: true });
      fs.copyFileSync(serverCert, path.join(dir, "trusted", "certs", "nclink-opcua.pem"));
      const cm = new OPCUACertificateManager({ rootFolder: dir, automaticallyAcceptUnknownCertificate: false });
      await cm.initialize();
      return { cm, connect: () => connect(opcua, url, { securityMode: MessageSecurityMode.SignAndEncrypt, securityPolicy: SecurityPolicy.Basic256Sha256, certificateManager: cm }) };
    };
    const strangerDir = tempDir("nclink-opcua-client-pki-");
    const stranger = await secureClient(strangerDir);
    const known = await secureClient(knownClientPki);
    try {
      // Unknown to the server: refused, its certificate kept in rejected/ for
      // an administrator to move to trusted/certs/.
      await assert.rejects(stranger.connect(), /BadSecurityChecksFailed/);
      await waitUntil(() => fs.readdirSync(path.join(pki, "rejected")).some((f) => /\.(pem|der)$/.test(f)), { what: "a certificate in rejected/" });
      // Trusted by the administrator (before the server started, see before()).
      const secure = await known.connect();
      try {
        assert.equal((await read("x_position", secure.session)).statusCode.name, "Good");
        const before = bridge.sets.length;
        assert.equal((await write("spindle_override", DataType.Double, 70, secure.session)).name, "Good");
        assert.deepEqual(bridge.sets.slice(before), [{ dev: DEV, id: "spindle_override", value: 70 }]);
      } finally {
        await secure.close();
      }
    } finally {
      await stranger.cm.dispose();
      await known.cm.dispose();
      fs.rmSync(strangerDir, { recursive: true, force: true });
    }
  });

  it("a user with the wrong password is refused, the right one accepted", async () => {
    await assert.rejects(
      connect(opcua, url, { userIdentity: { type: UserTokenType.UserName, userName: "operator", password: "wrong" } }),
      /BadUserAccessDenied|BadIdentityTokenRejected|BadIdentityTokenInvalid/,
    );
    await assert.rejects(connect(opcua, url, { userIdentity: { type: UserTokenType.UserName, userName: "nobody", password: "right-password" } }), /Bad/);
    const ok = await connect(opcua, url, { userIdentity: { type: UserTokenType.UserName, userName: "operator", password: "right-password" } });
    assert.equal((await read("x_position", ok.session)).statusCode.name, "Good");
    await ok.close();
  });

  it("a model change (new version) restarts the server with the new nodeset", async () => {
    const from = server.lines.length;
    const extra = { id: "coolant_on", dataType: "Boolean", encoding: "two_state", trueState: "on", falseState: "off", type: "COOLANT_ON" };
    bridge.changeModel(DEV, makeNodeset(testDevice(DEV, { extraItems: [extra] })), "2");
    await server.waitForLine(/model changed \(version 1 -> 2\)/, { from });
    await server.waitForLine(/serving 12 items/, { from });
    await server.waitForLine(/listening again/, { from });
    await c.close().catch(() => {});
    c = await waitUntil(() => connect(opcua, url), { ms: SETTLE_MS, every: 200, what: "reconnect after restart" });
    ns = (await c.session.readNamespaceArray()).indexOf(URI);
    assert.equal(await statusOf("coolant_on"), "BadWaitingForInitialData", "a new item waits for its first value");
    bridge.pushValue(DEV, "coolant_on", "on");
    await waitStatus("coolant_on", "Good");
    assert.equal((await read("coolant_on")).value.value, true);
    assert.equal((await read("x_position")).value.value, -3.5, "the cached values carry over");
  });

  it("a new model that does not load: the one before stays served", async () => {
    const from = server.lines.length;
    const v2 = makeNodeset(testDevice(DEV, { extraItems: [{ id: "coolant_on", dataType: "Boolean", encoding: "two_state", trueState: "on", falseState: "off", type: "COOLANT_ON" }] }));
    bridge.changeModel(DEV, v2.replace('DataType="Double"', 'DataType="NoSuchAlias"'), "3");
    await server.waitForLine(/nodeset \(version 3\) does not load/, { from });
    await server.waitForLine(/serving version 2 again/, { from });
    await server.waitForLine(/listening again/, { from });
    await c.close().catch(() => {});
    c = await waitUntil(() => connect(opcua, url), { ms: SETTLE_MS, every: 200, what: "reconnect after restart" });
    ns = (await c.session.readNamespaceArray()).indexOf(URI);
    await waitStatus("coolant_on", "Good");
    assert.equal((await read("x_position")).value.value, -3.5);
    // Version 3 is not fetched again for every event that repeats it.
    const requests = bridge.nodesetRequests.length;
    bridge.setState(DEV, "online");
    bridge.dropStreams();
    await server.waitForLine(/bridge stream open/, { from: server.lines.length - 1 });
    await new Promise((r) => setTimeout(r, 500));
    assert.equal(bridge.nodesetRequests.length, requests);
  });
});
