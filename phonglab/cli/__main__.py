import sys

from phonglab.cli import main

sys.exit(main())
