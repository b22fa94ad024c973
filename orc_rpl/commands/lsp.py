"""`orc lsp`: the language server for .rpl and .orl files, spoken over standard input and output (needs the [lsp] extra)."""

from __future__ import annotations

import argparse
import sys


def add_parser(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    parser = subparsers.add_parser(
        "lsp", help="run the language server for editors (stdio)",
        description="Run the language server for .rpl and .orl files over standard input and output: diagnostics "
                    "as you type, completion, hover, go to definition, outline and formatting. "
                    "docs/editors.md shows how VS Code and Neovim start it.")
    parser.add_argument("--stdio", action="store_true", help="talk over standard input and output (the default and only transport)")
    return parser


def run(args: argparse.Namespace) -> int:
    try:
        from orc_rpl.lsp.server import serve
    except ImportError as error:
        if error.name not in ("pygls", "lsprotocol") and not str(error.name).startswith(("pygls.", "lsprotocol.")):
            raise
        sys.stderr.write("orc lsp: error: the language server needs pygls; install it with: pip install 'orc_rpl[lsp]'\n")
        return 2
    serve()
    return 0
