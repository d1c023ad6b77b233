// Runs the Khronos glTF validator (npm gltf-validator, installed into web/node_modules by
// scripts/install-deps.sh) on each file named and prints one JSON line per file:
// {"file", "errors", "warnings", "messages": [{"code", "severity", "pointer", "message"}]}.
// Usage: node validate_gltf.mjs NODE_MODULES_DIR FILE...
import { createRequire } from 'module';
import fs from 'fs';
import path from 'path';

const require = createRequire(path.join(path.resolve(process.argv[2]), 'x.js'));
const validator = require('gltf-validator');
const severities = ['error', 'warning', 'info', 'hint'];
for (const file of process.argv.slice(3)) {
  const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
    uri: path.basename(file),
    maxIssues: 0,
    externalResourceFunction: (uri) => new Promise((resolve, reject) => {
      try {
        resolve(new Uint8Array(fs.readFileSync(path.join(path.dirname(file), decodeURIComponent(uri)))));
      } catch (e) {
        reject(String(e));
      }
    }),
  });
  console.log(JSON.stringify({
    file,
    errors: report.issues.numErrors,
    warnings: report.issues.numWarnings,
    messages: report.issues.messages.map((m) => ({
      code: m.code, severity: severities[m.severity], pointer: m.pointer ?? '', message: m.message,
    })),
  }));
}
