// Validates GLB/glTF files with the Khronos glTF validator; prints one JSON
// line per file ({file, errors, warnings, messages}) and exits 1 on any error.
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
const require = createRequire(import.meta.url);
const validator = require('gltf-validator');

let failed = false;
for (const file of process.argv.slice(2)) {
  const report = await validator.validateBytes(new Uint8Array(readFileSync(file)), {
    maxIssues: 50,
  });
  const errors = report.issues.numErrors;
  const messages = report.issues.messages
    .filter((m) => m.severity <= 1)
    .map((m) => `${m.severity === 0 ? 'error' : 'warning'} ${m.code} ${m.pointer ?? ''}: ${m.message}`);
  console.log(JSON.stringify({ file, errors, warnings: report.issues.numWarnings, messages }));
  if (errors > 0) failed = true;
}
process.exit(failed ? 1 : 0);
