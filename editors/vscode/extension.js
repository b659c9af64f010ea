// The golog++ extension: the language (package.json, language-configuration.json and the
// generated TextMate grammar do that without code), the language client for `gpp lsp` and the
// debugger `gpp dap`. Plain JavaScript, so that the extension needs no build step.
'use strict';

const vscode = require('vscode');
const { LanguageClient } = require('vscode-languageclient/node');

const LANGUAGE = 'golog';
const DEBUG_TYPE = 'gpp';

/** The `gpp` command of the settings (`gpp.path`). */
function gppCommand() {
  return vscode.workspace.getConfiguration('gpp').get('path', 'gpp') || 'gpp';
}

/** The language client of `gpp lsp`, for golog++ files on disk and unsaved ones. */
function languageClient(command) {
  const serverOptions = { command, args: ['lsp'] };
  const clientOptions = {
    documentSelector: [
      { scheme: 'file', language: LANGUAGE },
      { scheme: 'untitled', language: LANGUAGE },
    ],
  };
  return new LanguageClient('gpp', 'golog++ (gpp lsp)', serverOptions, clientOptions);
}

/** Starts `gpp dap` on stdio for each debug session. */
const debugAdapterFactory = {
  createDebugAdapterDescriptor() {
    return new vscode.DebugAdapterExecutable(gppCommand(), ['dap']);
  },
};

/** Fills in a launch for F5 without a launch.json: the golog++ file in the editor, stopped at
 * its first statement. Relative paths start from the workspace folder unless the launch says
 * `cwd`. A launch without a program or a trace is refused with a message. */
const debugConfigurationProvider = {
  resolveDebugConfiguration(folder, config) {
    let resolved = config;
    if (!config.type && !config.request && !config.name) {
      const editor = vscode.window.activeTextEditor;
      if (editor && editor.document.languageId === LANGUAGE) {
        resolved = {
          type: DEBUG_TYPE,
          request: 'launch',
          name: 'Debug the agent',
          program: editor.document.uri.fsPath,
          stopOnEntry: true,
        };
      }
    }
    if (!resolved.program && !resolved.trace) {
      return vscode.window
        .showInformationMessage('A golog++ launch needs a "program" to run or a "trace" to replay.')
        .then(() => undefined);
    }
    if (!resolved.cwd && folder) {
      resolved = { ...resolved, cwd: folder.uri.fsPath };
    }
    return resolved;
  },
};

/** The range of a golog++ expression under the mouse for the debugger's hover: a name, with its
 * arguments when it is called (`loc(a)`), and the fields read from it (`pose().x`). */
const evaluatableExpressionProvider = {
  provideEvaluatableExpression(document, position) {
    const word = document.getWordRangeAtPosition(position, /[A-Za-z_][A-Za-z0-9_]*/);
    if (!word) {
      return undefined;
    }
    const line = document.lineAt(position.line).text;
    const end = callEnd(line, word.end.character);
    return new vscode.EvaluatableExpression(new vscode.Range(word.start.line, word.start.character, word.start.line, end));
  },
};

/** Where the call starting at `from` ends (after its `)`) and the fields after it; `from` when
 * no `(` follows or it is not closed on the line. */
function callEnd(line, from) {
  let end = from;
  if (line[end] === '(') {
    let depth = 0;
    for (let i = end; i < line.length; i++) {
      if (line[i] === '(') {
        depth++;
      } else if (line[i] === ')' && --depth === 0) {
        end = i + 1;
        break;
      }
    }
    if (end === from) {
      return from;
    }
  }
  const field = /^\.[A-Za-z_][A-Za-z0-9_]*/.exec(line.slice(end));
  return field ? callEnd(line, end + field[0].length) : end;
}

let client;

function activate(context) {
  client = languageClient(gppCommand());
  client.start().catch((error) => {
    vscode.window.showErrorMessage(
      `golog++: could not start \`${gppCommand()} lsp\` (${error.message}); set "gpp.path" to the gpp command.`,
    );
  });
  context.subscriptions.push(
    vscode.debug.registerDebugAdapterDescriptorFactory(DEBUG_TYPE, debugAdapterFactory),
    vscode.debug.registerDebugConfigurationProvider(DEBUG_TYPE, debugConfigurationProvider),
    vscode.languages.registerEvaluatableExpressionProvider(LANGUAGE, evaluatableExpressionProvider),
  );
  return { languageClient: client };
}

/** Stops `gpp lsp` when it is starting or running (not when it could not be started). */
function deactivate() {
  return client && client.needsStop() ? client.stop() : undefined;
}

module.exports = { activate, deactivate };
