// Runs the Khronos glTF validator on .glb files: prints each report's counts and its errors, exits
// 1 when any file has an error (warnings and infos are printed, not fatal), 2 when a file is
// unreadable. Usage: node validate.mjs FILE.glb...
import { readFile } from 'node:fs/promises';
import validator from 'gltf-validator';

let failed = false;
for (const path of process.argv.slice(2)) {
    let bytes;
    try {
        bytes = new Uint8Array(await readFile(path));
    } catch (e) {
        console.error(`${path}: ${e.message}`);
        process.exit(2);
    }
    const report = await validator.validateBytes(bytes, { maxIssues: 100 });
    const { numErrors, numWarnings, numInfos, numHints } = report.issues;
    console.log(`${path}: ${numErrors} errors, ${numWarnings} warnings, ${numInfos} infos, ${numHints} hints`);
    for (const m of report.issues.messages) {
        if (m.severity <= 1) console.log(`  ${m.severity === 0 ? 'error' : 'warning'} ${m.code} ${m.pointer ?? ''}: ${m.message}`);
    }
    if (numErrors > 0) failed = true;
}
process.exit(failed ? 1 : 0);
