"use strict";
// The command line's failures (one line, the right exit status) and a
// locked-down server: Basic256Sha256 only, no anonymous sessions, users, the
// cnc profile with the OPC 40502 nodeset.
const { describe, it, before, after } = require("node:test");
const assert = require("node:assert/strict");
const fs = require("node:fs");
const net = require("node:net");

const opcua = require("../lib/node-opcua");
const { FakeBridge } = require("./support/fake-bridge");
const { makeNodeset, testDevice, CNC_URI } = require("./support/fake-nodeset");
const { tempDir, freePort, startServer, runToExit, connect } = require("./support/harness");

const { AttributeIds, MessageSecurityMode, SecurityPolicy, UserTokenType, OPCUACertificateManager, OPCUAClient } = opcua;
const DEV = "fake-lathe-2";

opcua.debug.setWarningLogger(() => {});

describe("command line", () => {
  it("a malformed bridge URL: exit 2 and one clear line", async () => {
    const r = await runToExit(["--bridge", "localhost:5000"]);
    assert.equal(r.code, 2);
    assert.equal(r.output.trim().split("\n").length, 1, r.output);
    assert.match(r.output, /^nclink-opcua: --bridge: "localhost:5000" is not an http:\/\/ or https:\/\/ URL/);
  });

  it("a taken port: exit 1 and one clear line", async () => {
    const blocker = net.createServer();
    await new Promise((resolve) => blocker.listen(0, "127.0.0.1", resolve));
    const { port } = blocker.address();
    const pki = tempDir("nclink-opcua-pki-");
    try {
      const r = await runToExit(["--bridge", "http://127.0.0.1:9", "--port", String(port), "--pki", pki]);
      assert.equal(r.code, 1, r.output);
      const errors = r.output.trim().split("\n").filter((l) => l.startsWith("nclink-opcua:"));
      assert.deepEqual(errors, [`nclink-opcua: port ${port} on 127.0.0.1 is already in use`], r.output);
    } finally {
      blocker.close();
      fs.rmSync(pki, { recursive: true, force: true });
    }
  });

  it("--help prints the usage and exits 0", async () => {
    const r = await runToExit(["--help"]);
    assert.equal(r.code, 0);
    assert.match(r.output, /^usage: nclink-opcua --bridge URL/);
  });
});

describe("Basic256Sha256 only, users only, cnc profile", () => {
  let bridge;
  let server;
  let url;
  let clientPki;
  let certificateManager;
  const secure = (userIdentity) =>
    connect(opcua, url, { securityMode: MessageSecurityMode.SignAndEncrypt, securityPolicy: SecurityPolicy.Basic256Sha256, certificateManager, userIdentity });
  const alice = { type: UserTokenType.UserName, userName: "alice", password: "s3cret" };

  before(async () => {
    bridge = new FakeBridge();
    bridge.addDevice({ dev: DEV, nodeset: makeNodeset(testDevice(DEV), { cnc: true }), values: { x_position: 1.5 } });
    await bridge.start();
    const port = await freePort();
    url = `opc.tcp://127.0.0.1:${port}`;
    server = startServer([
      "--bridge", bridge.url, "--port", String(port), "--security", "basic256sha256",
      "--no-anonymous", "--user", "alice:s3cret", "--profile", "cnc", "--accept-unknown-certs",
    ]);
    await server.waitForLine(/device fake-lathe-2: serving 11 items/);
    clientPki = tempDir("nclink-opcua-client-pki-");
    // The client takes the server's certificate on first use; the server
    // takes the client's because of --accept-unknown-certs.
    certificateManager = new OPCUACertificateManager({ rootFolder: clientPki, automaticallyAcceptUnknownCertificate: true });
  });

  after(async () => {
    if (certificateManager) await certificateManager.dispose();
    if (server) await server.stop();
    if (bridge) await bridge.stop();
    if (clientPki) fs.rmSync(clientPki, { recursive: true, force: true });
  });

  it("the server's PKI lives in the state directory, not in HOME's node-opcua default", () => {
    assert.ok(fs.existsSync(`${server.home}/state/nclink-opcua/pki/own/certs/certificate.pem`));
    assert.ok(!fs.existsSync(`${server.home}/.config`), "nothing under ~/.config");
  });

  it("offers only Basic256Sha256 endpoints and no anonymous token", async () => {
    const client = OPCUAClient.create({ endpointMustExist: false, clientCertificateManager: certificateManager, connectionStrategy: { maxRetry: 0 } });
    await client.connect(url);
    const endpoints = await client.getEndpoints();
    await client.disconnect();
    assert.ok(endpoints.length >= 2);
    for (const ep of endpoints) {
      assert.match(ep.securityPolicyUri, /#Basic256Sha256$/);
      assert.ok([MessageSecurityMode.Sign, MessageSecurityMode.SignAndEncrypt].includes(ep.securityMode));
      assert.ok(!ep.userIdentityTokens.some((t) => t.tokenType === UserTokenType.Anonymous), "no anonymous token policy");
    }
  });

  it("a session without security is refused", async () => {
    await assert.rejects(connect(opcua, url), /./);
  });

  it("an anonymous session is refused", async () => {
    // node-opcua's client will not even try without an anonymous token policy...
    await assert.rejects(secure(undefined), /ANONYMOUS user token policy/);
    // ...so make it believe there is one: the server itself must refuse.
    const s = await secure(alice);
    try {
      const endpoint = s.session.endpoint;
      endpoint.userIdentityTokens = [...endpoint.userIdentityTokens, { policyId: "anonymous", tokenType: UserTokenType.Anonymous }];
      const status = await s.client.changeSessionIdentity(s.session, { type: UserTokenType.Anonymous });
      assert.match(status.name, /^Bad(IdentityTokenInvalid|IdentityTokenRejected|UserAccessDenied)$/);
    } finally {
      await s.close();
    }
  });

  it("a bad password is refused, alice gets in", async () => {
    await assert.rejects(secure({ ...alice, password: "guess" }), /Bad/);
    const s = await secure(alice);
    try {
      const ns = (await s.session.readNamespaceArray()).indexOf(`urn:nclink:device:${DEV}`);
      const dv = await s.session.read({ nodeId: `ns=${ns};s=x_position`, attributeId: AttributeIds.Value });
      assert.equal(dv.statusCode.name, "Good");
      assert.equal(dv.value.value, 1.5);
    } finally {
      await s.close();
    }
  });

  it("profile cnc: the bridge is asked for it, OPC 40502 types resolve", async () => {
    assert.deepEqual(bridge.nodesetRequests.map((r) => r.profile), ["cnc"]);
    const s = await secure(alice);
    try {
      const namespaces = await s.session.readNamespaceArray();
      const cnc = namespaces.indexOf(CNC_URI);
      const ns = namespaces.indexOf(`urn:nclink:device:${DEV}`);
      assert.ok(cnc > 0, "the CNC namespace is loaded");
      const refs = await s.session.browse({ nodeId: `ns=${ns};s=axis_x`, referenceTypeId: "HasTypeDefinition", browseDirection: 0, resultMask: 63 });
      assert.equal(refs.references[0].nodeId.namespace, cnc);
      assert.equal(refs.references[0].browseName.name, "CncAxisType");
    } finally {
      await s.close();
    }
  });
});
