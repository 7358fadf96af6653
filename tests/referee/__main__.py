"""``python -m tests.referee`` (from the repository root): see :mod:`run`."""

import os
import sys

if __name__ == "__main__":
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    from referee.run import main

    sys.exit(main())
