#!/usr/bin/env node
// validate-gltf.mjs - runs the Khronos glTF validator (npm gltf-validator) on a .glb/.gltf.
//
// Usage: node tools/validate-gltf.mjs FILE [--baseline ORIGINAL]
// Prints one JSON object: {file, errors, warnings, infos, hints, messages: [{code, severity,
// message, pointer}]}; with --baseline also the baseline's counts and `new_warnings`, the
// warning codes FILE has more often than ORIGINAL (pointers differ after a rewrite, so
// warnings are compared by code and count). Exit 0 when FILE has no errors (and no new
// warnings against a baseline), 1 when it has, 2 when the validator cannot run at all.
// External files of a .gltf are read from its directory; nothing is fetched from the network.
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const severities = ['error', 'warning', 'info', 'hint'];

async function loadValidator() {
  return import(path.join(here, 'node_modules', 'gltf-validator', 'module.mjs'));
}

async function validate(validator, file) {
  const bytes = new Uint8Array(fs.readFileSync(file));
  const dir = path.dirname(path.resolve(file));
  const report = await validator.validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 0,
    externalResourceFunction: (uri) => new Promise((resolve, reject) => {
      const decoded = decodeURIComponent(uri);
      const full = path.resolve(dir, decoded);
      if (/^[a-z][a-z0-9+.-]*:/i.test(decoded) || !full.startsWith(dir + path.sep)) {
        reject(`refusing to read ${uri}`);
        return;
      }
      fs.readFile(full, (err, data) => (err ? reject(err.toString()) : resolve(new Uint8Array(data))));
    }),
  });
  const issues = report.issues;
  return {
    file,
    errors: issues.numErrors,
    warnings: issues.numWarnings,
    infos: issues.numInfos,
    hints: issues.numHints,
    messages: issues.messages.map((m) => ({
      code: m.code, severity: severities[m.severity] ?? String(m.severity), message: m.message, pointer: m.pointer,
    })),
  };
}

function warningCounts(result) {
  const counts = new Map();
  for (const m of result.messages)
    if (m.severity === 'warning') counts.set(m.code, (counts.get(m.code) ?? 0) + 1);
  return counts;
}

async function main(argv) {
  const args = argv.slice(2);
  let file = null, baseline = null;
  for (let i = 0; i < args.length; i++) {
    if (args[i] === '--baseline') baseline = args[++i];
    else if (file === null) file = args[i];
    else throw new Error(`unexpected argument ${args[i]}`);
  }
  if (!file || (args.includes('--baseline') && !baseline))
    throw new Error('usage: validate-gltf.mjs FILE [--baseline ORIGINAL]');
  const validator = await loadValidator();
  const result = await validate(validator, file);
  let failed = result.errors > 0;
  if (baseline) {
    const base = await validate(validator, baseline);
    const before = warningCounts(base), after = warningCounts(result);
    result.baseline = { file: baseline, errors: base.errors, warnings: base.warnings, infos: base.infos };
    result.new_warnings = [...after].filter(([code, n]) => n > (before.get(code) ?? 0)).map(([code]) => code);
    failed = failed || result.new_warnings.length > 0;
  }
  process.stdout.write(JSON.stringify(result, null, 2) + '\n');
  return failed ? 1 : 0;
}

main(process.argv).then((code) => process.exit(code), (err) => {
  process.stderr.write(`validate-gltf: ${err && err.message ? err.message : err}\n`);
  process.exit(2);
});
