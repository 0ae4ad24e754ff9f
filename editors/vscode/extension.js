// The VKG extension: starts `vkgc lsp` (configurable with `vkg.server.command`)
// over stdio for .vkg files. Highlighting comes from syntaxes/vkg.tmLanguage.json.
const vscode = require("vscode");
const { LanguageClient } = require("vscode-languageclient/node");

let client;

function activate(context) {
  const [command, ...args] = vscode.workspace
    .getConfiguration("vkg")
    .get("server.command", ["vkgc", "lsp"]);
  const server = { command, args };
  client = new LanguageClient(
    "vkg",
    "VKG language server",
    { run: server, debug: server },
    { documentSelector: [{ scheme: "file", language: "vkg" }] }
  );
  context.subscriptions.push(client);
  return client.start();
}

function deactivate() {
  return client ? client.stop() : undefined;
}

module.exports = { activate, deactivate };
