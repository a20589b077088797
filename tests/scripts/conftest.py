"""pytest setup for the result scripts' tests: scripts/ is on the path (pytest.ini: pythonpath), so
that `harness_results` (the package scripts/study.py and claims.py run on) imports as they import
it. Run by ctest (scripts:pytest) or: /usr/bin/python3 -m pytest -q tests/scripts"""
