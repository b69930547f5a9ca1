"use strict";
// ctest entry point: runs `node --test FILE...` when what the tests need is
// there, else says what is missing and exits 77 (ctest SKIP_RETURN_CODE).
//   node run-if-ready.js [--need-modules] [--need-file PATH]... FILE...
const { spawnSync } = require("node:child_process");
const fs = require("node:fs");
const path = require("node:path");

const SKIP = 77;
const args = process.argv.slice(2);
const files = [];
const needFiles = [];
let needModules = false;
for (let i = 0; i < args.length; i++) {
  if (args[i] === "--need-modules") needModules = true;
  else if (args[i] === "--need-file") needFiles.push(args[++i]);
  else files.push(args[i]);
}

function skip(why) {
  process.stdout.write(`skipped: ${why}\n`);
  process.exit(SKIP);
}

const major = Number(process.versions.node.split(".")[0]);
if (major < 18) skip(`Node.js ${process.versions.node} is older than 18`);
if (needModules) {
  const dir = path.join(__dirname, "..");
  try {
    require.resolve("node-opcua-server", { paths: [dir] });
  } catch {
    skip(`node-opcua is not installed in ${dir} (tools/install-deps.sh runs npm ci there)`);
  }
}
for (const f of needFiles) if (!fs.existsSync(f)) skip(`${f} does not exist (not built yet)`);

const r = spawnSync(process.execPath, ["--test", "--test-reporter=spec", ...files], { stdio: "inherit" });
process.exit(r.status === null ? 1 : r.status);
