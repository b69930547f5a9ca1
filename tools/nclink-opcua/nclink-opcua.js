#!/usr/bin/env node
"use strict";
// nclink-opcua: an OPC UA server for the devices of an nclink-bridge
// (docs/opcua.md). Thin: parse the command line, wire the pieces, run until
// SIGINT/SIGTERM.
const { parseOptions, UsageError, usage } = require("./lib/options");
const { createLogger, routeLibraryLogs } = require("./lib/log");
const { version } = require("./package.json");

function fail(message, status) {
  process.stderr.write(`nclink-opcua: ${message}\n`);
  process.exit(status);
}

async function main() {
  let options;
  try {
    options = parseOptions(process.argv.slice(2));
  } catch (e) {
    if (e instanceof UsageError) fail(`${e.message} (--help for usage)`, 2);
    throw e;
  }
  if (options.help) {
    process.stdout.write(`${usage}\n`);
    return;
  }
  if (options.version) {
    process.stdout.write(`nclink-opcua ${version}\n`);
    return;
  }

  const log = createLogger();
  let opcua;
  try {
    opcua = require("./lib/node-opcua");
  } catch (e) {
    fail(`node-opcua is not installed next to nclink-opcua.js (${e.code || e.message}); run npm ci in ${__dirname}`, 1);
  }
  routeLibraryLogs(opcua.debug, log);
  const { ServerHost, PortInUseError } = require("./lib/server-host");
  const { BridgeClient } = require("./lib/bridge-client");
  const { BridgeStream } = require("./lib/bridge-stream");
  const { Gateway } = require("./lib/gateway");

  const gateway = new Gateway({
    opcua,
    options,
    log,
    host: new ServerHost({ opcua, options, log, version }),
    bridge: new BridgeClient(options.bridge, { timeoutMs: options.requestTimeoutMs, callTimeoutMs: options.callTimeoutMs }),
    stream: new BridgeStream(options.bridge, { reconnectMaxMs: options.reconnectMaxMs, idleMs: options.streamIdleMs }),
  });

  log.info(`nclink-opcua ${version} starting: bridge ${options.bridge}, profile ${options.profile}`);
  try {
    await gateway.start();
  } catch (e) {
    if (e instanceof PortInUseError) fail(e.message, 1);
    fail(`cannot start the OPC UA server: ${e.message}`, 1);
  }

  let stopping = false;
  const stop = async (signal) => {
    if (stopping) return;
    stopping = true;
    log.info(`${signal}: stopping`);
    const force = setTimeout(() => process.exit(0), 5000);
    force.unref();
    await gateway.stop().catch((e) => log.error(`while stopping: ${e.message}`));
    process.exit(0);
  };
  process.on("SIGINT", () => stop("SIGINT"));
  process.on("SIGTERM", () => stop("SIGTERM"));
}

main().catch((e) => fail(`fatal: ${e && e.stack ? e.stack : e}`, 1));
