"""The language server: syntax and checking for editors (`orc lsp`); pygls is imported only here."""
