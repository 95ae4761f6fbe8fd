// Runs the Khronos glTF validator (npm package gltf-validator) on one .glb and prints its report
// as JSON. Usage: NODE_PATH=<node_modules> node validate-gltf.js FILE.glb
'use strict';
const fs = require('fs');
const validator = require('gltf-validator');
const file = process.argv[2];
const bytes = new Uint8Array(fs.readFileSync(file));
validator
  .validateBytes(bytes, { uri: file, maxIssues: 100 })
  .then((report) => {
    process.stdout.write(JSON.stringify(report, null, 1));
  })
  .catch((e) => {
    process.stderr.write('validator failed: ' + e + '\n');
    process.exit(2);
  });
