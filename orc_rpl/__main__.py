"""`python -m orc_rpl` is the `orc` command."""

from orc_rpl.cli import main

raise SystemExit(main())
