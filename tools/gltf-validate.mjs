// Checks glTF files with Khronos's glTF validator (the `gltf-validator` package on npm) and prints
// each file's counts of errors, warnings, infos and hints, then every message with its JSON
// pointer. Buffers and images the files name are read from beside them.
//
//     npm install gltf-validator && node tools/gltf-validate.mjs FILE...
import validator from 'gltf-validator';
import fs from 'fs';
import path from 'path';
for (const f of process.argv.slice(2)) {
  const data = new Uint8Array(fs.readFileSync(f));
  const dir = path.dirname(f);
  const report = await validator.validateBytes(data, {
    uri: f,
    externalResourceFunction: (uri) => new Promise((res, rej) => {
      try { res(new Uint8Array(fs.readFileSync(path.join(dir, decodeURIComponent(uri))))); } catch (e) { rej(e.toString()); }
    }),
  });
  const i = report.issues;
  console.log(f, 'errors', i.numErrors, 'warnings', i.numWarnings, 'infos', i.numInfos, 'hints', i.numHints);
  for (const m of i.messages) console.log('  ', m.severity, m.code, m.pointer, m.message);
}
