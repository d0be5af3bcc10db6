#!/usr/bin/env node
// Validates glTF 2.0 files with the Khronos glTF validator (npm package gltf-validator).
// Usage: node tools/validate_gltf.js FILE.glb|FILE.gltf ...
// Prints the number of errors and warnings of each file; exits 1 if any file has an error.
'use strict';
const fs = require('fs');
const path = require('path');
const validator = require('gltf-validator');

async function validate(file) {
  const data = new Uint8Array(fs.readFileSync(file));
  const report = await validator.validateBytes(data, {
    uri: path.basename(file),
    externalResourceFunction: (uri) =>
      new Promise((resolve, reject) => {
        fs.readFile(path.join(path.dirname(file), decodeURIComponent(uri)), (err, bytes) =>
          err ? reject(err.toString()) : resolve(new Uint8Array(bytes)));
      }),
  });
  const issues = report.issues;
  console.log(`${file}: ${issues.numErrors} errors, ${issues.numWarnings} warnings, ${issues.numInfos} infos`);
  for (const m of issues.messages) if (m.severity === 0) console.log(`  error ${m.code}: ${m.message} (${m.pointer || ''})`);
  return issues.numErrors;
}

(async () => {
  const files = process.argv.slice(2);
  if (files.length === 0) {
    console.error('usage: node tools/validate_gltf.js FILE.glb|FILE.gltf ...');
    process.exit(2);
  }
  let errors = 0;
  for (const f of files) errors += await validate(f);
  process.exit(errors > 0 ? 1 : 0);
})().catch((e) => {
  console.error(String(e));
  process.exit(1);
});
