// Validates glTF files with Khronos' glTF validator (npm package gltf-validator) and fails on any
// error. Warnings and infos are printed but pass.
//   node validate.js VALIDATOR_DIR FILE.glb...
// VALIDATOR_DIR is the npm prefix the package was installed into (install-validator.cmake).
'use strict';
const fs = require('fs');
const path = require('path');

const [prefix, ...files] = process.argv.slice(2);
if (!prefix || files.length === 0) {
  console.error('usage: node validate.js VALIDATOR_DIR FILE.glb...');
  process.exit(2);
}
const validator = require(path.resolve(prefix, 'node_modules', 'gltf-validator'));

(async () => {
  let failed = false;
  for (const file of files) {
    const bytes = new Uint8Array(fs.readFileSync(file));
    const report = await validator.validateBytes(bytes, {
      uri: path.basename(file),
      maxIssues: 0,  // all of them
      externalResourceFunction: () => Promise.reject(new Error('a .glb from weft-sim names no external file')),
    });
    const issues = report.issues;
    const info = report.info || {};
    console.log(`${file}: ${issues.numErrors} errors, ${issues.numWarnings} warnings, ${issues.numInfos} infos, ` +
                `${issues.numHints} hints; ${info.totalVertexCount} vertices, ${info.totalTriangleCount} triangles, ` +
                `${info.hasMorphTargets ? '' : 'no '}morph targets, ${info.animationCount} animation(s), ` +
                `validator ${report.validatorVersion}`);
    for (const m of issues.messages)
      console.log(`  ${['error', 'warning', 'info', 'hint'][m.severity]} ${m.code}: ${m.message} (${m.pointer || m.offset})`);
    if (issues.numErrors > 0) failed = true;
    if ((info.animationCount || 0) < 1 || !info.hasMorphTargets) {
      console.log(`  error: ${file} has no animation or no morph targets (weft-sim writes the run as both)`);
      failed = true;
    }
  }
  process.exit(failed ? 1 : 0);
})().catch((e) => {
  console.error(`validate.js: ${e.message || e}`);
  process.exit(1);
});
