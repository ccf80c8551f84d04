// gltf-transform <command> in.glb out.glb --config integrations/gltf-transform/pelt.config.mjs
// keeps pelt's PELT_fur extension (docs/pipelines.md).
import { ALL_EXTENSIONS } from '@gltf-transform/extensions';
import { PeltFur } from './src/index.js';

export default { extensions: [...ALL_EXTENSIONS, PeltFur] };
