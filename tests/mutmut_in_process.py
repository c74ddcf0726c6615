"""A pytest plugin that runs mutmut's mutants in one pytest process, each against the tests mutmut mapped to it.

mutmut 3 runs each mutant in a new process (``process_isolation = "forkserver"`` in ``pyproject.toml``), which here
imports numpy, the engines and the tests again: about a minute per mutant on two loaded cores.  This plugin keeps
one process: after ``mutmut run`` has generated ``mutants/`` and mapped each test to the functions it calls
(``mutants/mutmut-stats.json``; interrupt it once the mutants run), it switches each listed mutant on through
mutmut's trampoline (``MUTANT_UNDER_TEST``) and runs the tests mapped to the mutant's function, fastest first, the
fixtures kept between them and torn down after the last; the first failing test kills the mutant.  Run from
``mutants/`` (``docs/testing.md``)::

    cd mutants && MUTDRIVER_MUTANTS=names.txt MUTDRIVER_OUT=out.json PYTHONPATH=tests \
        python -m pytest -p mutmut_in_process -p no:cacheprovider -q --rootdir=. <the related test files>

``MUTDRIVER_MUTANTS``: a file of mutant names, one a line; ``MUTDRIVER_OUT``: the JSON of each one's status
(killed, survived, timeout, no tests), the test that killed it and its seconds, resumed where it stopped;
``MUTDRIVER_EXTRA``: test files (comma separated) run for every mutant besides its mapped tests (first, with
``MUTDRIVER_EXTRA_FIRST=1``): tests newer than the map; ``MUTDRIVER_TIMEOUT``: seconds per test (300).
Not a test file: pytest does not collect it.
"""

import json
import os
import signal
import time

from _pytest.runner import runtestprotocol
from mutmut.utils.format_utils import mangled_name_from_mutant_name


class _Timeout(Exception):
    pass


def _alarm(signum, frame):
    raise _Timeout()


def pytest_runtestloop(session):
    import crosscheck

    assert "/mutants/" in crosscheck.__file__, crosscheck.__file__
    stats = json.load(open("mutmut-stats.json"))
    tbf, dur = stats["tests_by_mangled_function_name"], stats["duration_by_test"]
    items = {it.nodeid: it for it in session.items}
    extra = [e for e in os.environ.get("MUTDRIVER_EXTRA", "").split(",") if e]
    names = [ln.strip() for ln in open(os.environ["MUTDRIVER_MUTANTS"]) if ln.strip()]
    out_path = os.environ["MUTDRIVER_OUT"]
    results = json.load(open(out_path)) if os.path.exists(out_path) else {}
    signal.signal(signal.SIGALRM, _alarm)
    for name in names:
        if name in results:
            continue
        mapped = [t for t in tbf.get(mangled_name_from_mutant_name(name), []) if t in items]
        # fastest first; a test of the rendered quick report pays its module fixture (about 13 s) once per mutant
        tests = sorted(mapped, key=lambda t: dur.get(t, 0.0) + 15.0 * ("rendered" in items[t].fixturenames))
        new = [t for t in items if any(t.startswith(e + "::") for e in extra) and t not in tests]
        tests = new + tests if os.environ.get("MUTDRIVER_EXTRA_FIRST") else tests + new
        res = {"status": "no tests", "killer": None, "n_tests": len(tests)}
        t0 = time.time()
        if tests:
            os.environ["MUTANT_UNDER_TEST"] = name
            res["status"] = "survived"
            for i, t in enumerate(tests):
                signal.alarm(int(os.environ.get("MUTDRIVER_TIMEOUT", "300")))
                try:  # (fixtures kept between this mutant's tests, torn down after its last)
                    nxt = items[tests[i + 1]] if i + 1 < len(tests) else None
                    reports = runtestprotocol(items[t], nextitem=nxt, log=False)
                except _Timeout:
                    reports = None
                finally:
                    signal.alarm(0)
                timed_out = reports is None or any(
                    r.failed and "_Timeout" in str(getattr(r, "longrepr", "")) for r in reports
                )
                if timed_out or any(r.failed for r in reports):
                    res["status"], res["killer"] = ("timeout" if timed_out else "killed"), t
                    break
            session._setupstate.teardown_exact(None)
            os.environ["MUTANT_UNDER_TEST"] = ""
        res["seconds"] = round(time.time() - t0, 1)
        results[name] = res
        with open(out_path, "w") as f:
            json.dump(results, f, indent=1)
        print(name, res["status"], res["killer"], res["seconds"], flush=True)
    return True
