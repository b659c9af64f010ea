// `gpp dap` driven by the official DebugClient of @vscode/debugadapter-testsupport, as VS Code
// drives it: launch, a breakpoint hit, stepping in, over and out, the variables, evaluate (and
// its located error) and a conditional breakpoint (and its located error), on the agent
// collect.gpp of tests/dap/test_vscode_client.py, which runs this as
// `node --test test/dap/scenario.test.js` with
//   GPP_COMMAND   the gpp command (the adapter is `GPP_COMMAND dap`)
//   GPP_PLATFORM  dummy or sim
//   GPP_PROGRAM   the agent's file (collect.gpp)
'use strict';

const assert = require('node:assert/strict');
const fs = require('node:fs');
const { test } = require('node:test');
const { DebugClient } = require('@vscode/debugadapter-testsupport');

const PROGRAM = process.env.GPP_PROGRAM;
const LINES = fs.readFileSync(PROGRAM, 'utf8').split('\n');
const PLATFORM = process.env.GPP_PLATFORM || 'dummy';
// The sim needs a world; the agent's actions have no mapping, so the world's scenario serves them.
const PLATFORM_OPTIONS = PLATFORM === 'sim' ? { world: 'blocksworld' } : {};
// Milliseconds the client waits for an answer or an event before the test fails.
const WAIT = 60000;

/** The 1-based line of the program that holds `text` (once). */
function lineOf(text) {
  const found = LINES.flatMap((line, i) => (line.includes(text) ? [i + 1] : []));
  assert.equal(found.length, 1, `the program has one line with ${text}`);
  return found[0];
}

async function frames(dc) {
  return (await dc.stackTraceRequest({ threadId: 1 })).body.stackFrames;
}

/** A request that moves the run (next, stepIn, ...) and the stop it leads to: the top frame. */
async function stepTo(dc, request, reason) {
  const [, stopped] = await Promise.all([
    request,
    dc.waitForEvent('stopped', WAIT).catch((error) => {
      throw new Error(`no stop for ${reason} (${error.message}); the events since: ${events.splice(0).join(', ')}`);
    }),
  ]);
  assert.equal(stopped.body.reason, reason, `stopped for ${reason}`);
  events.length = 0;
  return (await frames(dc))[0];
}

// The events since the last stop, to say what came instead of a stop.
const events = [];

async function variables(dc, reference) {
  return (await dc.variablesRequest({ variablesReference: reference })).body.variables;
}

/** The variables of the scope called `name` of the top frame, by name. */
async function scope(dc, name) {
  const top = (await frames(dc))[0];
  const scopes = (await dc.scopesRequest({ frameId: top.id })).body.scopes;
  const found = scopes.find((s) => s.name === name);
  assert.ok(found, `a scope ${name} among ${scopes.map((s) => s.name)}`);
  return Object.fromEntries((await variables(dc, found.variablesReference)).map((v) => [v.name, v]));
}

async function evaluate(dc, expression) {
  const top = (await frames(dc))[0];
  return (await dc.evaluateRequest({ expression, frameId: top.id, context: 'repl' })).body.result;
}

test(`gpp dap on the ${PLATFORM} platform, driven by the DebugClient`, { timeout: 4 * WAIT }, async () => {
  const dc = new DebugClient(process.env.GPP_COMMAND, 'dap', 'gpp', { cwd: __dirname });
  dc.defaultTimeout = WAIT;
  dc.on('output', (e) => events.push(`output ${JSON.stringify(e.body.output)}`));
  for (const name of ['stopped', 'exited', 'terminated']) {
    dc.on(name, (e) => events.push(`${name} ${JSON.stringify(e.body || {})}`));
  }
  await dc.start();
  try {
    // Launch with a breakpoint on main's first action: the run stops there.
    const first = lineOf('go(kitchen);');
    const launch = { program: PROGRAM, platform: PLATFORM, platformOptions: PLATFORM_OPTIONS };
    await dc.hitBreakpoint(launch, { path: PROGRAM, line: first });
    let stack = await frames(dc);
    assert.deepEqual(
      stack.map((f) => [f.name, f.line]),
      [['main()', first]],
    );

    // Step in: main's next statement is a call, which is no transition of its own: the stop is
    // at the call's first transition (the robot is in the kitchen already: the first pick-up),
    // with the caller at the call on the stack.
    const pickUp = lineOf('pick_up();');
    let top = await stepTo(dc, dc.stepInRequest({ threadId: 1 }), 'step');
    stack = await frames(dc);
    assert.deepEqual(
      stack.map((f) => [f.name, f.line]),
      [
        ['collect(kitchen)', pickUp],
        ['main()', lineOf('collect(kitchen);')],
      ],
    );

    // The variables: the parameter, and the fluents with each instance's value.
    const args = await scope(dc, 'Arguments');
    assert.equal(args.r.value, 'kitchen');
    const fluents = await scope(dc, 'Fluents');
    assert.equal(fluents['robot_at()'].value, 'kitchen');
    assert.equal(fluents['carried()'].value, '0');
    const cups = fluents[Object.keys(fluents).find((name) => name.startsWith('cups('))];
    assert.ok(cups.variablesReference > 0, 'cups has instances to expand');
    const instances = Object.fromEntries((await variables(dc, cups.variablesReference)).map((v) => [v.name, v.value]));
    assert.deepEqual(instances, { 'cups(office)': '0', 'cups(kitchen)': '2', 'cups(lab)': '1' });

    // Evaluate in the stopped situation, with the frame's parameter; a type error is located.
    assert.equal(await evaluate(dc, 'cups(r) + carried()'), '2');
    assert.equal(await evaluate(dc, 'robot_at() == r'), 'true');
    const error = await dc
      .evaluateRequest({ expression: 'cups(r) + robot_at()', frameId: stack[0].id, context: 'repl' })
      .then(
        () => assert.fail('a type error evaluates'),
        (e) => e.message,
      );
    assert.match(error, /^column 9: cannot add `number` and `Room`/);

    // Step over: the next transition of the same call, the second pick-up.
    top = await stepTo(dc, dc.nextRequest({ threadId: 1 }), 'step');
    assert.deepEqual([top.name, top.line], ['collect(kitchen)', pickUp]);
    assert.equal(await evaluate(dc, 'carried()'), '1');

    // A conditional breakpoint (a golog++ expression): one that does not type-check is refused
    // with the place of the error; then the pick-up with two cups carried, in the lab.
    const refused = await dc.setBreakpointsRequest({
      source: { path: PROGRAM },
      breakpoints: [{ line: pickUp, condition: 'carried() == lab' }],
    });
    assert.equal(refused.body.breakpoints[0].verified, false);
    assert.match(refused.body.breakpoints[0].message, /^the condition does not check: column 11: cannot compare `number` with/);
    const set = await dc.setBreakpointsRequest({
      source: { path: PROGRAM },
      breakpoints: [{ line: pickUp, condition: 'carried() == 2' }],
    });
    assert.equal(set.body.breakpoints[0].verified, true);
    top = await stepTo(dc, dc.continueRequest({ threadId: 1 }), 'breakpoint');
    assert.deepEqual([top.name, top.line], ['collect(lab)', pickUp]);
    assert.equal(await evaluate(dc, 'carried()'), '2');
    assert.equal(await evaluate(dc, 'r'), 'lab');
    assert.equal(await evaluate(dc, 'robot_at()'), 'lab');

    // Step out: back in main at the statement after the call, the lab's cup collected.
    await dc.setBreakpointsRequest({ source: { path: PROGRAM }, breakpoints: [] });
    top = await stepTo(dc, dc.stepOutRequest({ threadId: 1 }), 'step');
    assert.deepEqual(
      (await frames(dc)).map((f) => [f.name, f.line]),
      [['main()', lineOf('go(office);')]],
    );
    assert.equal(await evaluate(dc, 'carried()'), '3');

    // The run goes on to its end.
    const [, exited] = await Promise.all([
      dc.continueRequest({ threadId: 1 }),
      dc.waitForEvent('exited', WAIT),
      dc.waitForEvent('terminated', WAIT),
    ]);
    assert.equal(exited.body.exitCode, 0);
  } finally {
    await dc.stop();
  }
});
