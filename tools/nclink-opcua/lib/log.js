"use strict";
// One line per event that matters, on stderr: "<UTC time> <level> <message>".
// Messages never span lines, so the log stays greppable and journald-friendly.
const util = require("node:util");

function oneLine(parts) {
  return util.format(...parts).replace(/\s*\r?\n\s*/g, " | ");
}

function createLogger({ write = (line) => process.stderr.write(line), now = () => new Date() } = {}) {
  const emit = (level, parts) => write(`${now().toISOString()} ${level} ${oneLine(parts)}\n`);
  return {
    info: (...parts) => emit("info", parts),
    warn: (...parts) => emit("warn", parts),
    error: (...parts) => emit("error", parts),
  };
}

/// node-opcua prints its warnings and errors through node-opcua-debug, several
/// console lines each; route them into the log as single lines. W27 (RSA PKCS#1
/// v1.5 needs --security-revert on this Node) concerns only the Basic128Rsa15
/// policy, which this server never offers, so it is dropped.
function routeLibraryLogs(debug, log) {
  const forward = (level) => (_ctx, ...args) => {
    const text = oneLine(args);
    if (text.includes("NODE-OPCUA-W27") || text.includes("--security-revert=CVE-2023-46809")) return;
    log[level](`node-opcua: ${text}`);
  };
  debug.setWarningLogger(forward("warn"));
  debug.setErrorLogger(forward("error"));
}

module.exports = { createLogger, routeLibraryLogs, oneLine };
