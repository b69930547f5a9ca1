"use strict";
// The node-opcua server: endpoints, security, users, certificates, and the
// base nodesets (namespace 0, the CNC companion for --profile cnc, --nodeset
// files). Device nodesets are added to the running address space by the
// gateway. node-opcua cannot take a namespace out of a running address space
// again (its type nodes stay registered), so a device whose model changed is
// reloaded by building a fresh server: restart() with the same options.
const crypto = require("node:crypto");
const fs = require("node:fs");
const os = require("node:os");
const path = require("node:path");
const { StreamSampling } = require("./stream-sampling");

const PRODUCT_URI = "urn:nclink:opcua";

/// The shortest sampling interval a monitored item is given (ms).
/// node-opcua floors every requested sampling interval at
/// MonitoredItem.minimumSamplingInterval (50 ms by default), then at the
/// variable's MinimumSamplingInterval. The mapping writes a SAMPLE_CHANNEL
/// item's MinimumSamplingInterval as the channel's sampleInterval (table
/// B.7; 1 ms for a 1 ms channel), so with the library's floor at 1 ms (the
/// finest sampleInterval NC-Link can state) that attribute alone decides: a
/// client asking 10 ms of a 1 ms position is sampled every 10 ms, not every
/// 50 ms, and nobody gets faster than the item's channel.
const SAMPLING_FLOOR_MS = 1;

function sha256(text) {
  return crypto.createHash("sha256").update(text, "utf8").digest();
}

/// node-opcua's isValidUser: constant-time comparison of password digests.
function makeUserCheck(users) {
  const table = new Map(users.map((u) => [u.name, sha256(u.password)]));
  return (userName, password) => {
    const expected = table.get(userName);
    const given = sha256(typeof password === "string" ? password : "");
    return Boolean(expected) && crypto.timingSafeEqual(expected, given);
  };
}

class PortInUseError extends Error {}

class ServerHost {
  constructor({ opcua, options, log, version }) {
    this.opcua = opcua;
    this.options = options;
    this.log = log;
    this.version = version;
    this.server = null;
  }

  get addressSpace() {
    return this.server ? this.server.engine.addressSpace : null;
  }

  baseNodesets() {
    const { nodesets } = this.opcua;
    const list = [nodesets.standard];
    if (this.options.profile === "cnc") list.push(nodesets.cnc); // OPC 40502, needs namespace 0 only
    return list.concat(this.options.nodesets);
  }

  endpointSecurity() {
    const { SecurityPolicy, MessageSecurityMode } = this.opcua;
    const policies = this.options.securityPolicies.map((p) => SecurityPolicy[p]);
    const modes = [];
    if (this.options.securityPolicies.includes("None")) modes.push(MessageSecurityMode.None);
    if (this.options.securityPolicies.some((p) => p !== "None")) modes.push(MessageSecurityMode.Sign, MessageSecurityMode.SignAndEncrypt);
    return { securityPolicies: policies, securityModes: modes };
  }

  createServer() {
    const { OPCUAServer, OPCUACertificateManager, MonitoredItem } = this.opcua;
    // A class-wide setting of node-opcua-server (one server per process here).
    MonitoredItem.minimumSamplingInterval = SAMPLING_FLOOR_MS;
    const o = this.options;
    fs.mkdirSync(o.pki, { recursive: true, mode: 0o700 });
    const serverCertificateManager = new OPCUACertificateManager({
      rootFolder: o.pki,
      name: "PKI",
      automaticallyAcceptUnknownCertificate: o.acceptUnknownCertificates,
    });
    // X509 user tokens are not offered; node-opcua still wants a store for
    // them, and without one it would create it under $HOME.
    const userCertificateManager = new OPCUACertificateManager({
      rootFolder: path.join(o.pki, "user"),
      name: "UserPKI",
      automaticallyAcceptUnknownCertificate: false,
    });
    return new OPCUAServer({
      port: o.port,
      host: o.host,
      hostname: o.hostname,
      ...this.endpointSecurity(),
      allowAnonymous: o.allowAnonymous,
      userManager: { isValidUser: makeUserCheck(o.users) },
      serverCertificateManager,
      userCertificateManager,
      nodesets: this.baseNodesets(),
      serverInfo: {
        applicationUri: `urn:${os.hostname()}:nclink-opcua`,
        productUri: PRODUCT_URI,
        applicationName: { text: "nclink-opcua", locale: "en" },
      },
      buildInfo: { productName: "nclink-opcua", productUri: PRODUCT_URI, manufacturerName: "nclink", softwareVersion: this.version },
      isAuditing: false,
      maxConnectionsPerEndpoint: 64,
      // Values arrive pushed by the bridge, so a variable whose
      // MinimumSamplingInterval is 0 is served on change: with 0 here a
      // client asking for sampling interval 0 gets every change (a status
      // going running -> holding -> running), not one per 50 ms window.
      serverCapabilities: { maxSessions: 64, minSupportedSampleRate: 0 },
    });
  }

  /// Builds the address space, lets `beforeListen(addressSpace)` add to it,
  /// then listens. Throws PortInUseError when the port is taken.
  async start(beforeListen = async () => {}) {
    const server = this.createServer();
    this.server = server;
    new StreamSampling({ opcua: this.opcua }).install(server);
    try {
      await server.initialize();
      // Acknowledge, Confirm, ... of the alarms (lib/alarms.js).
      server.engine.addressSpace.installAlarmsAndConditionsService();
      await beforeListen(server.engine.addressSpace);
    } catch (e) {
      this.server = null;
      await server.shutdown(0).catch(() => {});
      throw e;
    }
    try {
      await server.start();
    } catch (e) {
      this.server = null;
      await server.shutdown(0).catch(() => {});
      const text = `${e && e.message} ${e && e.code}`;
      if (/EADDRINUSE/.test(text)) throw new PortInUseError(`port ${this.options.port} on ${this.options.host} is already in use`);
      if (/EADDRNOTAVAIL|EACCES/.test(text)) throw new PortInUseError(`cannot listen on ${this.options.host}:${this.options.port}: ${e.message}`);
      throw e;
    }
  }

  endpointUrls() {
    if (!this.server) return [];
    return [...new Set(this.server.endpoints.flatMap((ep) => ep.endpointDescriptions().map((d) => d.endpointUrl)))];
  }

  /// A NodeSet2 document into the running address space.
  async load(name, xml) {
    await this.opcua.generateAddressSpace(this.addressSpace, [{ name, source: xml }]);
  }

  async stop(graceMs = 0) {
    const server = this.server;
    this.server = null;
    if (server) await server.shutdown(graceMs);
  }

  async restart(beforeListen, graceMs = 500) {
    await this.stop(graceMs);
    await this.start(beforeListen);
  }
}

module.exports = { ServerHost, PortInUseError, makeUserCheck, SAMPLING_FLOOR_MS };
