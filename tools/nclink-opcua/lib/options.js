"use strict";
// Command line of nclink-opcua: parsed and checked before anything starts, so
// a mistake ends the program with one clear line and exit status 2.
const fs = require("node:fs");
const os = require("node:os");
const path = require("node:path");
const { parseArgs } = require("node:util");

const usage = `usage: nclink-opcua --bridge URL [options]
  Serves every device of an nclink-bridge as OPC UA (GB/T 39561.3 appendix B),
  values live from the bridge's stream, writes turned into NC-Link Sets.
  --bridge URL            the bridge, e.g. http://127.0.0.1:5000 (required)
  --port N                OPC UA TCP port (default 4840)
  --host ADDR             address to listen on (default 127.0.0.1; 0.0.0.0 = all)
  --hostname NAME         host name in the endpoint URLs (default: ADDR, or this
                          machine's name when ADDR is a wildcard)
  --security LIST         endpoints: none, basic256sha256 (Sign and SignAndEncrypt),
                          comma-separated (default none,basic256sha256)
  --no-anonymous          refuse anonymous sessions (needs --user or --user-file)
  --user NAME:PASSWORD    a user allowed to log in (repeatable)
  --user-file FILE        users, one NAME:PASSWORD per line ('#' comments)
  --pki DIR               certificates: own/, trusted/, rejected/
                          (default $XDG_STATE_HOME/nclink-opcua/pki)
  --accept-unknown-certs  trust every client certificate on first use (testing only)
  --profile basic|cnc     nodeset profile asked of the bridge (default basic; cnc
                          also loads the OPC 40502 CNC nodeset)
  --nodeset FILE          another NodeSet2 to load at start, e.g. a companion
                          specification a device nodeset requires (repeatable)
  --request-timeout MS    timeout of a request to the bridge (default 10000)
  --call-timeout MS       how long an OPC UA method call waits for the machine's
                          result before it is answered BadTimeout (default 60000)
  --reconnect-max MS      longest wait between stream reconnects (default 10000)
  --stream-idle MS        reconnect when the stream is silent this long (default 45000)
  --help, --version
exit status: 0 stopped by a signal, 1 runtime failure (port taken, ...), 2 usage error`;

class UsageError extends Error {}

const POLICIES = { none: "None", basic256sha256: "Basic256Sha256" };

/// The bridge base URL: http(s), a host, no query, fragment or credentials.
/// Returns the URL without a trailing slash (paths are appended to it).
function parseBridgeUrl(text) {
  let url;
  try {
    url = new URL(text);
  } catch {
    throw new UsageError(`--bridge: malformed URL "${text}" (expected e.g. http://127.0.0.1:5000)`);
  }
  if (url.protocol !== "http:" && url.protocol !== "https:")
    throw new UsageError(`--bridge: "${text}" is not an http:// or https:// URL`);
  if (!url.hostname) throw new UsageError(`--bridge: "${text}" has no host`);
  if (url.search || url.hash) throw new UsageError(`--bridge: "${text}" must not have a query or fragment`);
  if (url.username || url.password) throw new UsageError(`--bridge: "${text}" must not carry credentials`);
  return url.href.replace(/\/+$/, "");
}

function parseInteger(option, text, min, max) {
  if (!/^\d+$/.test(text)) throw new UsageError(`${option} needs a number, not "${text}"`);
  const n = Number(text);
  if (n < min || n > max) throw new UsageError(`${option} must be in ${min}..${max}`);
  return n;
}

/// "NAME:PASSWORD" -> {name, password}; the password may contain ':'.
function parseUser(text, where) {
  const colon = text.indexOf(":");
  if (colon <= 0 || colon === text.length - 1)
    throw new UsageError(`${where}: expected NAME:PASSWORD, got "${colon < 0 ? text : text.slice(0, colon) + ":..."}"`);
  return { name: text.slice(0, colon), password: text.slice(colon + 1) };
}

function readUserFile(file) {
  let text;
  try {
    text = fs.readFileSync(file, "utf8");
  } catch (e) {
    throw new UsageError(`--user-file: cannot read ${file}: ${e.code || e.message}`);
  }
  const users = [];
  text.split(/\r?\n/).forEach((line, i) => {
    const trimmed = line.trim();
    if (trimmed === "" || trimmed.startsWith("#")) return;
    users.push(parseUser(trimmed, `${file}:${i + 1}`));
  });
  return users;
}

function defaultPkiDir(env) {
  const state = env.XDG_STATE_HOME || path.join(env.HOME || os.homedir(), ".local", "state");
  return path.join(state, "nclink-opcua", "pki");
}

/// argv (without node and the script) -> options, or throws UsageError.
/// {help: true} / {version: true} when those were asked for.
function parseOptions(argv, env = process.env) {
  let parsed;
  try {
    parsed = parseArgs({
      args: argv,
      strict: true,
      allowPositionals: false,
      options: {
        bridge: { type: "string" },
        port: { type: "string" },
        host: { type: "string" },
        hostname: { type: "string" },
        security: { type: "string" },
        "no-anonymous": { type: "boolean" },
        user: { type: "string", multiple: true },
        "user-file": { type: "string" },
        pki: { type: "string" },
        "accept-unknown-certs": { type: "boolean" },
        profile: { type: "string" },
        nodeset: { type: "string", multiple: true },
        "request-timeout": { type: "string" },
        "call-timeout": { type: "string" },
        "reconnect-max": { type: "string" },
        "stream-idle": { type: "string" },
        help: { type: "boolean", short: "h" },
        version: { type: "boolean" },
      },
    });
  } catch (e) {
    throw new UsageError(e.message.split("\n")[0]);
  }
  const v = parsed.values;
  if (v.help) return { help: true };
  if (v.version) return { version: true };
  if (v.bridge === undefined) throw new UsageError("--bridge URL is required");

  const options = {
    bridge: parseBridgeUrl(v.bridge),
    port: v.port === undefined ? 4840 : parseInteger("--port", v.port, 1, 65535),
    host: v.host === undefined ? "127.0.0.1" : v.host,
    hostname: v.hostname,
    securityPolicies: [],
    allowAnonymous: !v["no-anonymous"],
    users: [],
    pki: path.resolve(v.pki === undefined ? defaultPkiDir(env) : v.pki),
    acceptUnknownCertificates: Boolean(v["accept-unknown-certs"]),
    profile: v.profile === undefined ? "basic" : v.profile,
    nodesets: (v.nodeset || []).map((f) => path.resolve(f)),
    requestTimeoutMs: v["request-timeout"] === undefined ? 10000 : parseInteger("--request-timeout", v["request-timeout"], 1, 600000),
    callTimeoutMs: v["call-timeout"] === undefined ? 60000 : parseInteger("--call-timeout", v["call-timeout"], 1, 3600000),
    reconnectMaxMs: v["reconnect-max"] === undefined ? 10000 : parseInteger("--reconnect-max", v["reconnect-max"], 1, 600000),
    streamIdleMs: v["stream-idle"] === undefined ? 45000 : parseInteger("--stream-idle", v["stream-idle"], 1, 3600000),
  };
  if (options.host === "") throw new UsageError("--host must not be empty");
  if (options.hostname === undefined)
    options.hostname = ["0.0.0.0", "::", "[::]"].includes(options.host) ? os.hostname() : options.host;

  const security = v.security === undefined ? "none,basic256sha256" : v.security;
  for (const word of security.split(",").map((s) => s.trim().toLowerCase())) {
    if (!(word in POLICIES)) throw new UsageError(`--security: unknown "${word}" (known: ${Object.keys(POLICIES).join(", ")})`);
    if (!options.securityPolicies.includes(POLICIES[word])) options.securityPolicies.push(POLICIES[word]);
  }

  for (const text of v.user || []) options.users.push(parseUser(text, "--user"));
  if (v["user-file"] !== undefined) options.users.push(...readUserFile(v["user-file"]));
  const names = new Set();
  for (const u of options.users) {
    if (names.has(u.name)) throw new UsageError(`user "${u.name}" given twice`);
    names.add(u.name);
  }
  if (!options.allowAnonymous && options.users.length === 0)
    throw new UsageError("--no-anonymous needs at least one --user or --user-file (nobody could log in)");

  if (options.profile !== "basic" && options.profile !== "cnc")
    throw new UsageError(`--profile must be basic or cnc, not "${options.profile}"`);
  for (const f of options.nodesets)
    if (!fs.existsSync(f)) throw new UsageError(`--nodeset: no such file ${f}`);
  return options;
}

module.exports = { parseOptions, parseBridgeUrl, UsageError, usage };
