// Runs Khronos' glTF Validator (npm gltf-validator) on one glTF file and prints one line: the
// validator's error count, its first error code, and the file. The validator's requirement that
// POSITION accessors carry min/max is muted: hrpp computes bounds itself and loads such files
// on purpose. Used by tests/gltf/validate.sh, one process a file (the validator can overflow its
// stack on deeply nested JSON, which ends the process).
// Usage: node validate.mjs VALIDATOR_MODULE_DIR FILE
import fs from 'node:fs';
import path from 'node:path';
import { createRequire } from 'node:module';

const [moduleDir, file] = process.argv.slice(2);
const validator = createRequire(path.join(moduleDir, 'index.js'))(moduleDir);
const readResource = (uri) =>
  new Promise((resolve, reject) => {
    fs.readFile(path.join(path.dirname(file), decodeURIComponent(uri)), (err, data) =>
      err ? reject(err.toString()) : resolve(new Uint8Array(data)));
  });

try {
  const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
    uri: path.basename(file),
    maxIssues: 20,
    ignoredIssues: ['MESH_PRIMITIVE_POSITION_ACCESSOR_WITHOUT_BOUNDS'],
    externalResourceFunction: readResource,
  });
  const errors = report.issues.messages.filter((m) => m.severity === 0);
  console.log(`${report.issues.numErrors}\t${errors.length ? errors[0].code : '-'}\t${file}`);
} catch (e) {
  console.log(`1\tVALIDATOR_FAILED\t${file}`);
}
