// Validates glTF files with the Khronos glTF-Validator (npm gltf-validator).
// Usage: node validate.mjs [--errors-only] [--list LISTFILE] FILE... ; prints one line per file
// (errors, warnings, infos) and every error and warning; exits 1 when any file has an error,
// 2 on usage errors. --list reads more paths from LISTFILE (one per line; paths that no longer
// exist are counted and skipped: tests remove some of what they write). --errors-only prints
// only the files with errors and the summary.
import { readFile } from 'node:fs/promises';
import { existsSync, readFileSync } from 'node:fs';
import path from 'node:path';
import validator from 'gltf-validator';

const args = process.argv.slice(2);
const files = [];
let errorsOnly = false;
let gone = 0;
for (let k = 0; k < args.length; k++) {
  if (args[k] === '--errors-only') {
    errorsOnly = true;
  } else if (args[k] === '--list') {
    const lines = readFileSync(args[++k], 'utf8').split('\n').filter((l) => l.length > 0);
    for (const l of lines) {
      if (existsSync(l)) files.push(l);
      else gone++;
    }
  } else {
    files.push(args[k]);
  }
}
if (files.length === 0) {
  console.error('usage: node validate.mjs [--errors-only] [--list LISTFILE] FILE...');
  process.exit(2);
}
let failed = 0;
for (const file of files) {
  const bytes = new Uint8Array(await readFile(file));
  const dir = path.dirname(file);
  let report;
  try {
    report = await validator.validateBytes(bytes, {
      uri: file,
      maxIssues: 0,
      externalResourceFunction: (uri) =>
        readFile(path.resolve(dir, decodeURIComponent(uri))).then((b) => new Uint8Array(b)),
    });
  } catch (e) {
    console.log(`${file}: not readable as glTF: ${e}`);
    failed++;
    continue;
  }
  const i = report.issues;
  if (errorsOnly && i.numErrors === 0) continue;
  console.log(`${file}: ${i.numErrors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos`);
  for (const m of i.messages) {
    if (m.severity <= (errorsOnly ? 0 : 1)) {
      console.log(`  ${m.severity === 0 ? 'error' : 'warning'} ${m.code} ${m.pointer ?? ''}: ${m.message}`);
    }
  }
  if (i.numErrors > 0) failed++;
}
const skipped = gone > 0 ? ` (${gone} listed files no longer exist)` : '';
console.log(`${files.length - failed} passed, ${failed} failed${skipped}`);
process.exit(failed > 0 ? 1 : 0);
