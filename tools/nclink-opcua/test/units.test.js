"use strict";
// The pure pieces of nclink-opcua: no OPC UA stack, no sockets.
const test = require("node:test");
const assert = require("node:assert/strict");
const fs = require("node:fs");
const os = require("node:os");
const path = require("node:path");

const { SseParser } = require("../lib/sse");
const { parseOptions, parseBridgeUrl, UsageError } = require("../lib/options");
const { toVariant, fromVariant } = require("../lib/values");
const { setAnswerStatus, setFailureStatus, itemStatus } = require("../lib/status");
const { scanNodeset } = require("../lib/nodeset-info");
const { backoffDelay } = require("../lib/bridge-stream");
const { oneLine } = require("../lib/log");
const { methodsOf, argsOf, callArgs, callAnswerStatus } = require("../lib/methods");
const { due } = require("../lib/stream-sampling");
const { makeNodeset, testDevice, itemIds } = require("./support/fake-nodeset");

test("sse: events, data lines joined, comments, CRLF split across chunks", () => {
  const p = new SseParser();
  const all = [];
  for (const chunk of [": ping\r", "\n\r\nevent: value\r\ndata: {\"a\":", "1}\r\n", "data: x\r\n\r", "\n", "data: plain\n\n"]) all.push(...p.push(chunk));
  assert.deepEqual(all, [
    { comment: "ping" },
    { type: "value", data: '{"a":1}\nx', id: undefined },
    { type: "message", data: "plain", id: undefined },
  ]);
});

test("sse: an event without data is not dispatched, fields without colon are names", () => {
  const p = new SseParser();
  assert.deepEqual(p.push("event: device\n\ndata\n\nid: 7\nevent:snapshot\ndata:{}\n\n"), [
    { type: "message", data: "", id: undefined },
    { type: "snapshot", data: "{}", id: "7" },
  ]);
});

test("options: defaults and the documented flags", () => {
  const o = parseOptions(["--bridge", "http://127.0.0.1:5000/"], { HOME: "/home/u" });
  assert.equal(o.bridge, "http://127.0.0.1:5000");
  assert.equal(o.port, 4840);
  assert.equal(o.host, "127.0.0.1");
  assert.equal(o.hostname, "127.0.0.1");
  assert.deepEqual(o.securityPolicies, ["None", "Basic256Sha256"]);
  assert.equal(o.allowAnonymous, true);
  assert.equal(o.pki, "/home/u/.local/state/nclink-opcua/pki");
  assert.equal(o.profile, "basic");
  const s = parseOptions(["--bridge", "http://h:1/x", "--security", "basic256sha256", "--no-anonymous", "--user", "op:pa:ss", "--pki", "/tmp/p", "--profile", "cnc", "--port", "4841"], { XDG_STATE_HOME: "/s" });
  assert.equal(s.bridge, "http://h:1/x");
  assert.deepEqual(s.securityPolicies, ["Basic256Sha256"]);
  assert.deepEqual(s.users, [{ name: "op", password: "pa:ss" }]);
  assert.equal(s.allowAnonymous, false);
  assert.equal(s.pki, "/tmp/p");
  assert.equal(s.port, 4841);
  assert.equal(parseOptions(["--bridge", "http://h:1"], { XDG_STATE_HOME: "/s" }).pki, "/s/nclink-opcua/pki");
});

test("options: every mistake is a UsageError with a clear message", () => {
  const bad = [
    [[], /--bridge URL is required/],
    [["--bridge", "127.0.0.1:5000"], /malformed URL/],
    [["--bridge", "localhost:5000"], /not an http/],
    [["--bridge", "http//x"], /malformed URL/],
    [["--bridge", "ftp://x"], /not an http/],
    [["--bridge", "http://x/?a=1"], /query or fragment/],
    [["--bridge", "http://u:p@x"], /credentials/],
    [["--bridge", "http://x", "--port", "0"], /--port must be in 1..65535/],
    [["--bridge", "http://x", "--port", "48a"], /--port needs a number/],
    [["--bridge", "http://x", "--security", "basic128rsa15"], /unknown "basic128rsa15"/],
    [["--bridge", "http://x", "--no-anonymous"], /needs at least one --user/],
    [["--bridge", "http://x", "--user", "nopassword"], /NAME:PASSWORD/],
    [["--bridge", "http://x", "--user", "a:1", "--user", "a:2"], /given twice/],
    [["--bridge", "http://x", "--profile", "mtconnect"], /basic or cnc/],
    [["--bridge", "http://x", "--nodeset", "/no/such/file.xml"], /no such file/],
    [["--bridge", "http://x", "--frobnicate"], /Unknown option/],
    [["--bridge", "http://x", "stray"], /positional/],
  ];
  for (const [argv, re] of bad) assert.throws(() => parseOptions(argv, {}), (e) => e instanceof UsageError && re.test(e.message), argv.join(" "));
  assert.equal(parseBridgeUrl("https://bridge.example:8443"), "https://bridge.example:8443");
});

test("options: users from a file", () => {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), "nclink-opcua-"));
  const file = path.join(dir, "users");
  fs.writeFileSync(file, "# operators\nalice:s3cret\n\n bob:x:y \n");
  const o = parseOptions(["--bridge", "http://x", "--no-anonymous", "--user-file", file], {});
  assert.deepEqual(o.users, [{ name: "alice", password: "s3cret" }, { name: "bob", password: "x:y" }]);
  fs.writeFileSync(file, "alice\n");
  assert.throws(() => parseOptions(["--bridge", "http://x", "--user-file", file], {}), /users:1: expected NAME:PASSWORD/);
  fs.rmSync(dir, { recursive: true });
});

const META = {
  double: { dataType: "Double", encoding: "scalar" },
  int32: { dataType: "Int32", encoding: "scalar" },
  uint32: { dataType: "UInt32", encoding: "scalar" },
  text: { dataType: "String", encoding: "scalar" },
  flag: { dataType: "Boolean", encoding: "scalar" },
  json: { dataType: "String", encoding: "json" },
  mode: { dataType: "UInt32", encoding: "enum_index", enumStrings: ["forward", "stop", "reverse"] },
  words: { dataType: "Boolean", encoding: "two_state", trueState: "auto", falseState: "manual" },
  any: { dataType: "Variant", encoding: "scalar" },
  doubles: { dataType: "Double", encoding: "scalar", array: true },
};

test("values: NC-Link JSON to Variant per the mapping's encodings", () => {
  assert.deepEqual(toVariant(12.5, META.double), { dataType: "Double", value: 12.5 });
  assert.deepEqual(toVariant(" 7.25 ", META.double), { dataType: "Double", value: 7.25 });
  assert.deepEqual(toVariant("12", META.int32), { dataType: "Int32", value: 12 });
  assert.deepEqual(toVariant(true, META.flag), { dataType: "Boolean", value: true });
  assert.deepEqual(toVariant(0, META.flag), { dataType: "Boolean", value: false });
  assert.deepEqual(toVariant("O1000", META.text), { dataType: "String", value: "O1000" });
  assert.deepEqual(toVariant(42, META.text), { dataType: "String", value: "42" });
  assert.deepEqual(toVariant({ p: [1, 2] }, META.json), { dataType: "String", value: '{"p":[1,2]}' });
  assert.deepEqual(toVariant("x", META.json), { dataType: "String", value: '"x"' });
  assert.deepEqual(toVariant("reverse", META.mode), { dataType: "UInt32", value: 2 });
  assert.deepEqual(toVariant(1, META.mode), { dataType: "UInt32", value: 1 });
  assert.deepEqual(toVariant("manual", META.words), { dataType: "Boolean", value: false });
  assert.deepEqual(toVariant(true, META.words), { dataType: "Boolean", value: true });
  assert.deepEqual(toVariant(3, META.any), { dataType: "Double", value: 3 });
  assert.deepEqual(toVariant([1, 2], META.any), { dataType: "String", value: "[1,2]" });
  assert.deepEqual(toVariant([1, "2"], META.doubles), { dataType: "Double", value: [1, 2], array: true });
  assert.deepEqual(toVariant(null, META.double), { empty: true });
});

test("values: what does not convert is an error, never a guess", () => {
  for (const [json, meta] of [
    ["fast", META.double],
    [1.5, META.int32],
    [-1, META.uint32],
    [2 ** 31, META.int32],
    ["maybe", META.flag],
    ["sideways", META.mode],
    [3, META.mode],
    ["semi", META.words],
    [{}, META.double],
    [5, META.doubles],
  ])
    assert.ok(toVariant(json, meta).error, JSON.stringify([json, meta]));
});

test("values: OPC UA writes to NC-Link JSON", () => {
  assert.deepEqual(fromVariant({ dataType: "Double", value: 80 }, META.double), { json: 80 });
  assert.deepEqual(fromVariant({ dataType: "Int32", value: -4 }, META.int32), { json: -4 });
  assert.deepEqual(fromVariant({ dataType: "String", value: "O2000" }, META.text), { json: "O2000" });
  assert.deepEqual(fromVariant({ dataType: "String", value: '{"p1":3}' }, META.json), { json: { p1: 3 } });
  assert.deepEqual(fromVariant({ dataType: "UInt32", value: 2 }, META.mode), { json: "reverse" });
  assert.deepEqual(fromVariant({ dataType: "Boolean", value: false }, META.words, { wordsSeen: true }), { json: "manual" });
  assert.deepEqual(fromVariant({ dataType: "Boolean", value: false }, META.words), { json: false });
  assert.deepEqual(fromVariant({ dataType: "Double", value: [1, 2], array: true }, META.doubles), { json: [1, 2] });
  assert.deepEqual(fromVariant({ dataType: "Int64", value: [0, 5] }, { dataType: "Int64", encoding: "scalar" }), { json: 5 });
  assert.equal(fromVariant({ dataType: "String", value: "{oops" }, META.json).status, "BadTypeMismatch");
  assert.equal(fromVariant({ dataType: "UInt32", value: 3 }, META.mode).status, "BadOutOfRange");
  assert.equal(fromVariant({ dataType: "Double", value: Infinity }, META.double).status, "BadOutOfRange");
  assert.equal(fromVariant({ dataType: "Double", value: 1 }, META.words).status, "BadTypeMismatch");
});

test("status: Set answers (table 19) to Write results", () => {
  const cases = [
    [{ code: "OK" }, "Good"],
    [{ code: "NG", error: 101, reason: "Out of Range" }, "BadOutOfRange"],
    [{ code: "NG", error: 202, reason: "Unavailable" }, "BadCommunicationError"],
    [{ code: "NG", error: 203, reason: "Timeout" }, "BadTimeout"],
    [{ code: "NG", error: 301, reason: "Permission Denied" }, "BadUserAccessDenied"],
    [{ code: "NG", error: 301, reason: "DEV_UNREACHABLE" }, "BadCommunicationError"],
    [{ code: "NG", error: 401, reason: "Node not exists" }, "BadNodeIdUnknown"],
    [{ code: "NG", error: 404, reason: "Memory configured error" }, "BadOutOfMemory"],
    [{ code: "NG", error: 405, reason: "Value type error" }, "BadTypeMismatch"],
    [{ code: "NG", error: -7, reason: "vendor" }, "BadUnexpectedError"],
    [{ code: "NG" }, "BadUnexpectedError"],
  ];
  for (const [answer, status] of cases) assert.equal(setAnswerStatus(answer), status, JSON.stringify(answer));
  assert.equal(setFailureStatus("timeout"), "BadTimeout");
  assert.equal(setFailureStatus("unreachable"), "BadCommunicationError");
  assert.equal(setFailureStatus("http"), "BadCommunicationError");
});

test("status: an item's status, most important cause first", () => {
  const up = { bridgeUp: true, state: "online", live: true };
  const good = { hasValue: true, quality: "good", empty: false, convertible: true };
  assert.equal(itemStatus(up, good), "Good");
  assert.equal(itemStatus({ ...up, bridgeUp: false, state: "offline" }, good), "BadCommunicationError");
  assert.equal(itemStatus({ ...up, state: "offline" }, good), "BadNoCommunication");
  assert.equal(itemStatus({ ...up, state: "unknown" }, good), "BadWaitingForInitialData");
  assert.equal(itemStatus({ ...up, live: false }, good), "BadWaitingForInitialData");
  assert.equal(itemStatus(up, { ...good, hasValue: false }), "BadWaitingForInitialData");
  assert.equal(itemStatus(up, { ...good, quality: "bad" }), "BadDeviceFailure");
  assert.equal(itemStatus(up, { ...good, empty: true }), "BadDeviceFailure");
  assert.equal(itemStatus(up, { ...good, convertible: false }), "BadConfigurationError");
});

test("nodeset scan: namespaces, item extensions, fixed values", () => {
  const device = testDevice("mill <1>");
  const info = scanNodeset(makeNodeset(device));
  assert.deepEqual(info.namespaceUris, ["urn:nclink:device:mill <1>"]);
  assert.deepEqual([...info.items.keys()].sort(), itemIds(device).sort());
  assert.deepEqual(info.items.get("spindle_mode"), {
    id: "spindle_mode", nodeId: "ns=1;s=spindle_mode", stringId: "spindle_mode", encoding: "enum_index", datatype: "single", setable: true, type: "SPINDLE_MODE",
  });
  assert.equal(info.items.get("parameters").encoding, "json");
  assert.ok(info.withValue.has("ns=1;s=spindle_max_speed"));
  assert.ok(!info.withValue.has("ns=1;s=x_position"));
  assert.equal(scanNodeset(makeNodeset(device, { extensions: false })).items.size, 0);
  // Comments and other namespaces' Item elements are not extensions.
  const tricky = `<UANodeSet><!-- <Uri>no</Uri> --><NamespaceUris><Uri>urn:a&amp;b</Uri></NamespaceUris>
    <UAVariable NodeId="ns=1;s=a"><Extensions><Extension><x:Item xmlns:x="urn:other" id="a"/></Extension></Extensions></UAVariable></UANodeSet>`;
  const t = scanNodeset(tricky);
  assert.deepEqual(t.namespaceUris, ["urn:a&b"]);
  assert.equal(t.items.size, 0);
});

test("stream backoff: 250 ms doubling up to the maximum", () => {
  assert.deepEqual([0, 1, 2, 3, 4, 5, 6].map((a) => backoffDelay(a, 10000)), [250, 500, 1000, 2000, 4000, 8000, 10000]);
  assert.equal(backoffDelay(1000, 10000), 10000);
});

test("log: one line per message", () => {
  assert.equal(oneLine(["a\n  b", 3]), "a | b 3");
});

test("methods: the METHOD configs of the root and the device, their args, the call's args and status", () => {
  const model = {
    configs: [{ id: "a", type: "METHOD", args: {} }, { id: "v", type: "VERSION" }, { id: "a", type: "METHOD" }, { type: "METHOD" }],
    devices: [{ guid: "d1", configs: [{ id: "b", name: "B", type: "METHOD", args: ["x", { name: "y", default: 1 }] }] }, { guid: "d2", configs: [{ id: "c", type: "METHOD" }] }],
  };
  assert.deepEqual(methodsOf(model, "d1").map((m) => m.id), ["a", "b"]);
  assert.deepEqual(methodsOf(model, "d2").map((m) => m.id), ["a", "c"]);
  assert.deepEqual(methodsOf(null, "d1"), []);
  assert.deepEqual(argsOf(["x", { name: "y", default: 1 }, { name: "z", optional: true }, 7]).map((a) => [a.name, a.optional]), [["x", false], ["y", true], ["z", true]]);
  assert.deepEqual(argsOf({ p: 1, q: "s" }).map((a) => a.name), ["p", "q"]);
  assert.equal(argsOf(undefined), null);
  const declared = argsOf(["x", { name: "y", optional: true }]);
  assert.deepEqual(callArgs(declared, [{ value: "1" }, { value: "" }]), { args: { x: "1" } });
  assert.deepEqual(callArgs(declared, [{ value: "" }, { value: "2" }]), { args: { x: "", y: "2" } }, "a required one is sent even empty: the adapter says 102 if it must");
  assert.deepEqual(callArgs(null, [{ value: '{"k":1}' }]), { args: { k: 1 } });
  assert.deepEqual(callArgs(null, [{ value: "" }]), { args: {} });
  assert.equal(callArgs(null, [{ value: "3" }]).status, "BadInvalidArgument");
  assert.equal(callAnswerStatus({ code: "OK", result: "canceled" }), "Good");
  assert.equal(callAnswerStatus({ code: "NG", error: 401 }), "BadMethodInvalid");
  assert.equal(callAnswerStatus({ code: "NG", error: 203, reason: "DEV_UNREACHABLE" }), "BadCommunicationError");
  assert.equal(callAnswerStatus({ code: "NG", error: 1 }), "BadUnexpectedError");
});

test("stream sampling: a value is due one sampling interval after the last in its source time, or with a new status", () => {
  const dv = (ms, status = 0) => ({ sourceTimestamp: ms === undefined ? null : new Date(ms), statusCode: { value: status } });
  assert.equal(due(dv(1000), dv(1010), 10), true);
  assert.equal(due(dv(1000), dv(1009), 10), false);
  assert.equal(due(dv(1000), dv(1001), 1), true);
  assert.equal(due(dv(1000), dv(1000), 1), false);
  assert.equal(due(dv(1000), dv(1001, 0x80050000), 10), true, "a status change is always reported");
  assert.equal(due(dv(1000), dv(990), 10), true, "a clock that went back starts a new run");
  assert.equal(due(dv(undefined), dv(1000), 10), true);
  assert.equal(due(null, dv(1000), 10), true);
});
