from agents.regenerate.cli import main

raise SystemExit(main())
