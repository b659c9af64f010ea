// A stand-in for the `vscode` module, so that the extension can be loaded and activated by plain
// Node (VS Code itself is not downloaded in the tests). What the extension calls directly is
// written out and records what it was given (`recorded`); everything else the language client
// touches is `anything`: a function, a class and an object at once, whose every property and
// every call is another `anything`, and which is not a promise.
'use strict';

const Module = require('module');

function anything(name) {
  const target = function () {};
  return new Proxy(target, {
    get(_, key) {
      if (key === 'then') {
        return undefined;
      }
      if (key === Symbol.toPrimitive) {
        return () => `<${name}>`;
      }
      if (key === Symbol.iterator) {
        return function* () {};
      }
      if (key === 'prototype') {
        return target.prototype;
      }
      return anything(`${name}.${String(key)}`);
    },
    apply() {
      return anything(`${name}()`);
    },
    construct() {
      return anything(`new ${name}`);
    },
  });
}

function stubVscode(settings, activeDocument) {
  const recorded = { adapterFactories: {}, configurationProviders: {}, expressionProviders: {}, messages: [] };
  class Position {
    constructor(line, character) {
      this.line = line;
      this.character = character;
    }
  }
  class Range {
    constructor(startLine, startCharacter, endLine, endCharacter) {
      this.start = new Position(startLine, startCharacter);
      this.end = new Position(endLine, endCharacter);
    }
  }
  class DebugAdapterExecutable {
    constructor(command, args) {
      this.command = command;
      this.args = args;
    }
  }
  class EvaluatableExpression {
    constructor(range, expression) {
      this.range = range;
      this.expression = expression;
    }
  }
  const disposable = { dispose() {} };
  const explicit = {
    version: '1.82.0',
    env: new Proxy(
      { appName: 'Visual Studio Code', language: 'en' },
      { get: (target, key) => (key in target ? target[key] : anything(`env.${String(key)}`)) },
    ),
    Position,
    Range,
    DebugAdapterExecutable,
    EvaluatableExpression,
    workspace: new Proxy(
      {
        getConfiguration(section) {
          return { get: (key, fallback) => settings[`${section}.${key}`] ?? fallback };
        },
      },
      { get: (target, key) => (key in target ? target[key] : anything(`workspace.${String(key)}`)) },
    ),
    window: new Proxy(
      {
        activeTextEditor: activeDocument ? { document: activeDocument } : undefined,
        showInformationMessage(message) {
          recorded.messages.push(message);
          return Promise.resolve(undefined);
        },
        showErrorMessage(message) {
          recorded.messages.push(message);
          return Promise.resolve(undefined);
        },
      },
      { get: (target, key) => (key in target ? target[key] : anything(`window.${String(key)}`)) },
    ),
    debug: {
      registerDebugAdapterDescriptorFactory(type, factory) {
        recorded.adapterFactories[type] = factory;
        return disposable;
      },
      registerDebugConfigurationProvider(type, provider) {
        recorded.configurationProviders[type] = provider;
        return disposable;
      },
    },
    languages: new Proxy(
      {
        registerEvaluatableExpressionProvider(selector, provider) {
          recorded.expressionProviders[selector] = provider;
          return disposable;
        },
      },
      { get: (target, key) => (key in target ? target[key] : anything(`languages.${String(key)}`)) },
    ),
  };
  const vscode = new Proxy(explicit, {
    get: (target, key) => (key in target ? target[key] : anything(`vscode.${String(key)}`)),
  });
  return { vscode, recorded };
}

/** Makes `require('vscode')` return `vscode` from now on. */
function installVscode(vscode) {
  const load = Module._load;
  Module._load = function (request, ...rest) {
    return request === 'vscode' ? vscode : load.call(this, request, ...rest);
  };
}

module.exports = { stubVscode, installVscode };
