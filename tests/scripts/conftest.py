"""pytest setup for the result scripts' tests: scripts/ on the path, so that `harness_results` (the
package scripts/study.py and claims.py run on) imports as they import it. Run by ctest
(scripts:pytest) or: /usr/bin/python3 -m pytest -q tests/scripts"""

import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts"))
