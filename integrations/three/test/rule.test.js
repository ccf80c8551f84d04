import { test } from 'node:test';
import assert from 'node:assert/strict';
import { shellRule, shellsFor } from '../src/plugin.js';

// The same cases as pelt_fur::shells's unit test: the two implementations agree.
test('shells by screen size follow pelt_fur::shells::ShellRule::shells', () => {
  const r = shellRule({ shellRule: { pixelsPerShell: 1, min: 3 } }, 'm');
  const cases = [[0, 16, 3], [2.4, 16, 3], [3.8, 16, 4], [6, 16, 6], [10.6, 16, 11], [22, 16, 16],
    [1e30, 16, 16], [Infinity, 16, 16], [NaN, 16, 16], [0.5, 2, 2], [5, 0, 1]];
  for (const [px, max, want] of cases) assert.equal(shellsFor(r, px, max), want, `${px} px, at most ${max}`);
  assert.equal(shellsFor({ pixelsPerShell: 2, min: 1 }, 7, 64), 4);
  assert.equal(shellRule({}, 'm'), null);
  assert.throws(() => shellRule({ shellRule: { pixelsPerShell: 0, min: 1 } }, 'materials[0]'), /materials\[0\]\.shellRule\.pixelsPerShell/);
  assert.throws(() => shellRule({ shellRule: { pixelsPerShell: 1, min: 0 } }, 'm'), /min/);
});
