"""Running programs: one run end to end (runner), `gpp test` (testing), and what `gpp run`
shows while a program runs (view)."""
