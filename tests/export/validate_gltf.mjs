// Validates glTF files with the Khronos glTF-Validator (npm gltf-validator):
//   node validate_gltf.mjs FILE.glb|FILE.gltf...
// Prints each file's error/warning/info/hint counts and its first messages;
// exits 1 when any file has an error or a warning (infos and hints are fine).
import { readFile } from "node:fs/promises";
import path from "node:path";
import { createRequire } from "node:module";

const require = createRequire(import.meta.url);
const validator = require("gltf-validator");

let failed = 0;
for (const file of process.argv.slice(2)) {
  const data = new Uint8Array(await readFile(file));
  const report = await validator.validateBytes(data, {
    uri: path.basename(file),
    maxIssues: 0,
    // .gltf buffers are files beside the JSON.
    externalResourceFunction: (uri) =>
      readFile(path.join(path.dirname(file), decodeURIComponent(uri))).then((b) => new Uint8Array(b)),
  });
  const i = report.issues;
  console.log(`${file}: ${i.numErrors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos, ${i.numHints} hints`);
  for (const m of i.messages.slice(0, 10)) console.log(`  ${m.severity === 0 ? "error" : m.severity === 1 ? "warning" : "info"} ${m.code} ${m.pointer ?? ""}: ${m.message}`);
  if (i.numErrors || i.numWarnings) failed += 1;
}
process.exit(failed ? 1 : 0);
