"use strict";
// Test helpers: run nclink-opcua as a child process (as a user would), wait
// for its log lines, connect node-opcua clients, browse, poll.
const { spawn } = require("node:child_process");
const fs = require("node:fs");
const net = require("node:net");
const os = require("node:os");
const path = require("node:path");

const SCRIPT = path.join(__dirname, "..", "..", "nclink-opcua.js");

function tempDir(prefix = "nclink-opcua-test-") {
  return fs.mkdtempSync(path.join(os.tmpdir(), prefix));
}

async function freePort() {
  const server = net.createServer();
  await new Promise((resolve) => server.listen(0, "127.0.0.1", resolve));
  const { port } = server.address();
  await new Promise((resolve) => server.close(resolve));
  return port;
}

/// Polls `fn` until it returns a truthy value (returned) or `ms` pass (throws
/// with the last value or error).
async function waitUntil(fn, { ms = 20000, every = 50, what = "condition" } = {}) {
  const end = Date.now() + ms;
  let last;
  for (;;) {
    try {
      last = await fn();
      if (last) return last;
    } catch (e) {
      last = e;
    }
    if (Date.now() > end) throw new Error(`timed out waiting for ${what}; last: ${last && last.message ? last.message : JSON.stringify(last)}`);
    await new Promise((r) => setTimeout(r, every));
  }
}

/// nclink-opcua with `args`; its log is kept (and echoed with VERBOSE=1).
/// HOME points to a scratch folder: nothing may be written to the real one.
function serverEnv(home) {
  const env = { ...process.env, HOME: home, XDG_STATE_HOME: path.join(home, "state") };
  delete env.VERBOSE; // node-opcua-pki would print its certificate steps
  return env;
}

function startServer(args, { home = tempDir("nclink-opcua-home-") } = {}) {
  const proc = spawn(process.execPath, [SCRIPT, ...args], { stdio: ["ignore", "pipe", "pipe"], env: serverEnv(home) });
  const lines = [];
  let buffer = "";
  const onData = (chunk) => {
    buffer += chunk;
    let nl;
    while ((nl = buffer.indexOf("\n")) >= 0) {
      const line = buffer.slice(0, nl);
      buffer = buffer.slice(nl + 1);
      lines.push(line);
      if (process.env.VERBOSE) process.stderr.write(`    [server] ${line}\n`);
    }
  };
  proc.stdout.setEncoding("utf8").on("data", onData);
  proc.stderr.setEncoding("utf8").on("data", onData);
  const exited = new Promise((resolve) => proc.on("exit", (code, signal) => resolve({ code, signal })));
  return {
    proc,
    lines,
    home,
    exited,
    /// The first log line (from line `from` on) matching `re`.
    async waitForLine(re, { ms = 120000, from = 0 } = {}) {
      return waitUntil(() => lines.slice(from).find((l) => re.test(l)), { ms, what: `log line ${re}\n${lines.join("\n")}` });
    },
    async stop() {
      if (proc.exitCode === null && proc.signalCode === null) proc.kill("SIGTERM");
      const r = await exited;
      fs.rmSync(home, { recursive: true, force: true });
      return r;
    },
  };
}

/// Runs nclink-opcua to its exit -> {code, output}.
function runToExit(args, { ms = 60000 } = {}) {
  const home = tempDir("nclink-opcua-home-");
  return new Promise((resolve, reject) => {
    const proc = spawn(process.execPath, [SCRIPT, ...args], { env: serverEnv(home) });
    let output = "";
    proc.stdout.on("data", (c) => (output += c));
    proc.stderr.on("data", (c) => (output += c));
    const timer = setTimeout(() => {
      proc.kill("SIGKILL");
      reject(new Error(`nclink-opcua ${args.join(" ")} did not exit:\n${output}`));
    }, ms);
    proc.on("exit", (code) => {
      clearTimeout(timer);
      fs.rmSync(home, { recursive: true, force: true });
      resolve({ code, output });
    });
  });
}

/// A connected client session. options: {securityMode, securityPolicy,
/// userIdentity, certificateManager, clientPki}.
async function connect(opcua, endpointUrl, options = {}) {
  const { OPCUAClient, MessageSecurityMode, SecurityPolicy } = opcua;
  const client = OPCUAClient.create({
    applicationName: "nclink-opcua-test",
    endpointMustExist: false,
    securityMode: options.securityMode || MessageSecurityMode.None,
    securityPolicy: options.securityPolicy || SecurityPolicy.None,
    clientCertificateManager: options.certificateManager,
    connectionStrategy: { maxRetry: 0, initialDelay: 100 },
    requestedSessionTimeout: 60000,
  });
  await client.connect(endpointUrl);
  try {
    const session = await client.createSession(options.userIdentity);
    return {
      client,
      session,
      async close() {
        await session.close().catch(() => {});
        await client.disconnect();
      },
    };
  } catch (e) {
    await client.disconnect();
    throw e;
  }
}

/// Every variable with a string NodeId in namespace `ns` reachable by forward
/// hierarchical references from `start` -> Map<string id, browseName>.
async function browseVariables(opcua, session, start, ns) {
  const { NodeClass } = opcua;
  const found = new Map();
  const seen = new Set();
  const queue = [start];
  while (queue.length) {
    const nodeId = queue.shift();
    if (seen.has(nodeId)) continue;
    seen.add(nodeId);
    const result = await session.browse({ nodeId, referenceTypeId: "HierarchicalReferences", includeSubtypes: true, browseDirection: 0, resultMask: 63 });
    for (const r of result.references || []) {
      const id = r.nodeId;
      if (id.namespace !== ns) continue;
      if (r.nodeClass === NodeClass.Variable && typeof id.value === "string") found.set(id.value, r.browseName.toString());
      queue.push(id.toString());
    }
  }
  return found;
}

/// A program started with its standard output and error appended to
/// WORK/<its name>.log.
function spawnLogged(file, args, work) {
  const log = fs.openSync(path.join(work, `${path.basename(file)}.log`), "a");
  const proc = spawn(file, args, { stdio: ["ignore", log, log] });
  fs.closeSync(log);
  return proc;
}

/// SIGTERM, SIGKILL after 10 s; resolves when it has exited.
async function stopProcess(proc) {
  if (!proc || proc.exitCode !== null || proc.signalCode !== null) return;
  const exited = new Promise((resolve) => proc.on("exit", resolve));
  proc.kill("SIGTERM");
  const timer = setTimeout(() => proc.kill("SIGKILL"), 10000);
  await exited;
  clearTimeout(timer);
}

module.exports = { SCRIPT, tempDir, freePort, waitUntil, startServer, runToExit, connect, browseVariables, spawnLogged, stopProcess };
