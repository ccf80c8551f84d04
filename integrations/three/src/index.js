// @pelt/three: draws pelt's baked fur (the PELT_fur glTF extension) in three.js.
export { EXTENSION, PeltFurPlugin, furShared, furPixels, setWind, shellRule, shellsFor } from './plugin.js';
export { density, strandParams, sideFor } from './density.js';
export { indexHash } from './xxhash32.js';
