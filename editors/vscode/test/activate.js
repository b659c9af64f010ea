// Loads the extension under plain Node with a stand-in for `vscode` (test/stub_vscode.js),
// activates it with the `gpp` command given as the first argument and prints, as JSON, what it
// did: the debug adapter it starts, the launches it resolves, the expressions it hovers and
// whether its language client got `gpp lsp` running and stopped it again.
// Usage: node test/activate.js GPP_COMMAND PROGRAM
'use strict';

const { stubVscode, installVscode } = require('./stub_vscode');

const [gpp, program] = process.argv.slice(2);

function document(path, lines) {
  return {
    languageId: 'golog',
    uri: { fsPath: path },
    lineAt: (line) => ({ text: lines[line] }),
    getWordRangeAtPosition(position, pattern) {
      const text = lines[position.line];
      const word = new RegExp(pattern.source, 'g');
      for (let found; (found = word.exec(text)) !== null; ) {
        if (found.index <= position.character && position.character <= found.index + found[0].length) {
          return {
            start: { line: position.line, character: found.index },
            end: { line: position.line, character: found.index + found[0].length },
          };
        }
      }
      return undefined;
    },
  };
}

async function main() {
  const lines = ['    if (loc(a) == table) { x = pose().x; }'];
  const active = document(program, lines);
  const { vscode, recorded } = stubVscode({ 'gpp.path': gpp }, active);
  installVscode(vscode);
  const extension = require('../extension');
  const api = extension.activate({ subscriptions: [] });
  const report = {};

  const adapter = recorded.adapterFactories.gpp.createDebugAdapterDescriptor({});
  report.adapter = { command: adapter.command, args: adapter.args };

  const provider = recorded.configurationProviders.gpp;
  const folder = { uri: { fsPath: '/work/space' } };
  report.resolved = {
    empty: await provider.resolveDebugConfiguration(undefined, {}),
    program: await provider.resolveDebugConfiguration(undefined, { type: 'gpp', request: 'launch', name: 'p', program }),
    inFolder: await provider.resolveDebugConfiguration(folder, { type: 'gpp', request: 'launch', name: 'f', program }),
    neither: (await provider.resolveDebugConfiguration(undefined, { type: 'gpp', request: 'launch', name: 'n' })) ?? null,
  };
  report.refusal = recorded.messages.splice(0);

  const hover = recorded.expressionProviders.golog;
  report.hover = {};
  for (const word of ['loc', 'a', 'table', 'pose', 'x =', 'if']) {
    const at = lines[0].indexOf(word) + 1;
    const found = hover.provideEvaluatableExpression(active, { line: 0, character: at });
    report.hover[word] = lines[0].slice(found.range.start.character, found.range.end.character);
  }

  const client = api.languageClient;
  const deadline = Date.now() + 60000;
  while (!client.isRunning() && Date.now() < deadline && recorded.messages.length === 0) {
    await new Promise((resolve) => setTimeout(resolve, 50));
  }
  report.running = client.isRunning();
  report.server = client.initializeResult ? client.initializeResult.serverInfo : null;
  report.capabilities = client.initializeResult ? Object.keys(client.initializeResult.capabilities).sort() : [];
  await extension.deactivate();
  report.stopped = !client.isRunning();
  report.messages = recorded.messages;
  process.stdout.write(JSON.stringify(report) + '\n');
}

main().then(
  () => process.exit(0),
  (error) => {
    process.stderr.write(`${error.stack}\n`);
    process.exit(1);
  },
);
