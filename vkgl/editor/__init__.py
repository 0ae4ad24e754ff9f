"""Editor support for `.vkg`: a Pygments lexer, a TextMate grammar, and a language server.

A front-end tool: it imports only `vkgl.lang`, `vkgl.errors` and
`vkgl.resources` (never the simulator, inference or planner).

- `vocabulary`: the keywords, units and faces, read from `grammar/vkg.lark`.
- `lexer`: `VkgLexer` for Pygments (`pygmentize -l vkg`).
- `textmate`: builds and checks `editors/vscode/syntaxes/vkg.tmLanguage.json`.
- `server`: `vkgc lsp`, the language server (pygls, stdio).
"""
