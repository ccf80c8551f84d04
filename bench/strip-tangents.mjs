// Copies a .glb with TANGENT removed from every primitive (data left in place; only the JSON
// reference goes), so tangent generators can be compared on the same mesh.
// Usage: node strip-tangents.mjs IN.glb OUT.glb
import { readFile, writeFile } from 'node:fs/promises';

const [input, output] = process.argv.slice(2);
const b = await readFile(input);
const jsonLen = b.readUInt32LE(12);
const json = JSON.parse(b.subarray(20, 20 + jsonLen).toString('utf8'));
for (const m of json.meshes ?? []) for (const p of m.primitives) delete p.attributes.TANGENT;
let text = Buffer.from(JSON.stringify(json), 'utf8');
const pad = (4 - (text.length % 4)) % 4;
text = Buffer.concat([text, Buffer.alloc(pad, 0x20)]);
const rest = b.subarray(20 + jsonLen);
const header = Buffer.alloc(20);
header.write('glTF', 0);
header.writeUInt32LE(2, 4);
header.writeUInt32LE(20 + text.length + rest.length, 8);
header.writeUInt32LE(text.length, 12);
header.writeUInt32LE(0x4e4f534a, 16);
await writeFile(output, Buffer.concat([header, text, rest]));
