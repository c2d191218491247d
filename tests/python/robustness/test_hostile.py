"""Hostile input to every public callable (the table in `public_api.py`).

Each callable gets 300 hostile draws (one argument hostile, or several), refused before any
work, and a third of its table's `examples` draws of valid but extreme arguments (100; fewer
for the maps and figures, which compute and draw). The only outcomes allowed:

- with a hostile argument: TypeError or ValueError whose message names one of the hostile
  arguments;
- with valid arguments: a result that passes the entry's check (shapes, finiteness, the
  physics it promises), or a ValueError naming an argument (a run longer than `max_steps`,
  a step beyond the method's stability limit);
- never another exception, a Rust panic (PanicException derives from BaseException, which
  `except Exception` misses), a warning other than the package's own, or NaN in a result.

Derandomized: every run draws the same examples. Set DZ_HOSTILE_REPORT=path to write the
outcome counts of each callable as JSON.
"""

from __future__ import annotations

import inspect
import json
import os
import re
import warnings
from collections import Counter
from typing import Any

import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st
from public_api import NOT_CALLED, Entry
from public_api_batch import ENTRIES

import dzhanibekov as dz

OUTCOMES: dict[str, Counter[str]] = {}

PHASES = [Phase.explicit, Phase.reuse, Phase.generate] + (
    [] if os.environ.get("DZ_HOSTILE_NO_SHRINK") else [Phase.shrink])
"""Set DZ_HOSTILE_NO_SHRINK=1 to report failures unshrunk (faster when iterating)."""

SOAK = int(os.environ.get("DZ_HOSTILE_SOAK", "0"))
"""DZ_HOSTILE_SOAK=N: N random (not derandomized) examples per callable instead of the
table's, for a long search off CI."""


def parameters(entry: Entry) -> set[str]:
    try:
        signature = inspect.signature(entry.call).parameters
    except (TypeError, ValueError):
        return set(entry.hostile)
    names = {n for n, p in signature.items() if p.kind is not p.VAR_KEYWORD}
    if any(p.kind is p.VAR_KEYWORD for p in signature.values()):
        names |= set(dz.options.NAMES)  # typed **keywords: the run options (dz.RunKeywords)
    return names


def names_one_of(message: str, names: set[str] | tuple[str, ...], aliases: dict[str, tuple[str, ...]]) -> bool:
    """Whether `message` names one of `names` (or an alias) as a word."""
    for name in names:
        for alias in (name, *aliases.get(name, ())):
            if re.search(rf"(?<![A-Za-z0-9_]){re.escape(alias)}(?![A-Za-z0-9_])", message):
                return True
    return False


HOSTILE_EXAMPLES = 300
"""Hostile draws per callable: cheap, since every one is refused before any work."""


def examples(entry: Entry, kind: str) -> int:
    if SOAK:
        return SOAK
    return HOSTILE_EXAMPLES if kind == "hostile" else max(entry.examples // 3, 4)


@st.composite
def calls(draw: st.DrawFn, name: str, kind: str) -> tuple[dict[str, Any], tuple[str, ...]]:
    """Valid keyword arguments of entry `name`, for a `kind` "hostile" draw with one or several
    replaced by hostile values."""
    entry = ENTRIES[name]
    kwargs = dict(draw(entry.valid))
    names = sorted(entry.hostile)
    mode = draw(st.sampled_from(["one", "several"])) if kind == "hostile" else "valid"
    bad: list[str] = []
    if mode == "one":
        bad = [draw(st.sampled_from(names))]
    elif mode == "several":
        bad = draw(st.lists(st.sampled_from(names), min_size=1, max_size=len(names), unique=True))
    for name in bad:
        kwargs[name] = draw(entry.hostile[name])
    return kwargs, tuple(bad)


def call(entry: Entry, kwargs: dict[str, Any]) -> tuple[str, Any, list[warnings.WarningMessage]]:
    """Calls `entry` and sorts the outcome: ("ok", result) or ("error", exception). Any other
    exception fails here, a Rust panic by name."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            return "ok", entry.call(**kwargs), caught
        except (ValueError, TypeError) as exc:
            return "error", exc, caught
        except Exception as exc:
            pytest.fail(f"{type(exc).__name__} (not ValueError/TypeError): {exc}\nkwargs={kwargs!r}")
        except BaseException as exc:
            if type(exc).__name__ == "PanicException":
                pytest.fail(f"a Rust panic reached Python: {exc}\nkwargs={kwargs!r}")
            raise


@pytest.mark.parametrize("kind", ["hostile", "valid"])
@pytest.mark.parametrize("name", sorted(ENTRIES))
def test_hostile_input(name: str, kind: str) -> None:
    entry = ENTRIES[name]
    if kind == "hostile" and not entry.hostile:
        pytest.skip(f"{name} takes no arguments")
    counts: Counter[str] = Counter()
    accepted = parameters(entry)
    aliases = dict(entry.aliases)

    @settings(max_examples=examples(entry, kind), derandomize=not SOAK, database=None,
              deadline=None, suppress_health_check=list(HealthCheck), phases=PHASES)
    @given(calls(name, kind))
    def run(case: tuple[dict[str, Any], tuple[str, ...]]) -> None:
        kwargs, bad = case
        outcome, value, caught = call(entry, kwargs)
        stray = [w for w in caught if not issubclass(w.category, entry.warns)]
        assert not stray, f"unexpected warnings {[str(w.message) for w in stray]}\nkwargs={kwargs!r}"
        counts["calls"] += 1
        counts["hostile" if bad else "valid"] += 1
        if bad:
            assert outcome == "error", f"hostile {bad} accepted, returned {value!r}\nkwargs={kwargs!r}"
            quoted = any(str(kwargs[n]) in str(value) for n in bad
                         if n in entry.named_by_value and isinstance(kwargs[n], (str, os.PathLike))
                         and str(kwargs[n]))
            assert quoted or names_one_of(str(value), bad, aliases), \
                f"{type(value).__name__} does not name any of {bad}: {value}\nkwargs={kwargs!r}"
            counts[type(value).__name__] += 1
        elif outcome == "error":
            assert isinstance(value, ValueError), f"valid arguments, {type(value).__name__}: {value}\nkwargs={kwargs!r}"
            assert names_one_of(str(value), accepted, aliases), \
                f"valid arguments refused without naming one: {value}\nkwargs={kwargs!r}"
            counts["valid refused"] += 1
        else:
            with warnings.catch_warnings():  # the check may call the package again
                for category in entry.warns:
                    warnings.simplefilter("ignore", category)
                entry.check(kwargs, value, caught)
            counts["valid returned"] += 1

    run()
    OUTCOMES.setdefault(name, Counter()).update(counts)
    if kind == "hostile":
        assert counts["hostile"] == examples(entry, kind), counts
    else:
        assert counts["valid returned"] >= entry.min_success * counts["valid"], counts
    if path := os.environ.get("DZ_HOSTILE_REPORT"):
        try:
            with open(path, encoding="utf-8") as f:
                report = json.load(f)
        except (OSError, ValueError):
            report = {}
        report[name] = dict(OUTCOMES[name])
        with open(path, "w", encoding="utf-8") as f:
            json.dump(report, f, indent=1, sort_keys=True)


def test_every_public_name_is_in_the_table() -> None:
    """A public name added to `dz.__all__` must get an entry (or a reason not to)."""
    covered = {id(obj) for entry in ENTRIES.values() for obj in (entry.call, *entry.covers)}
    covered |= {id(getattr(entry.call, "__self__", None)) for entry in ENTRIES.values()}
    missing = [n for n in dz.__all__ if n not in NOT_CALLED and id(getattr(dz, n)) not in covered]
    assert not missing, f"public names without a hostile-input entry in public_api.py: {missing}"


def test_box_edges_takes_nothing_and_gives_the_twelve_edges() -> None:
    edges = dz.box_edges()
    assert edges.shape == (12, 2) and edges.min() == 0 and edges.max() == 7
    with pytest.raises(TypeError):
        dz.box_edges(1)  # type: ignore[call-arg]


# -- files ------------------------------------------------------------------------------------

FILE_OUTCOMES: dict[str, Counter[str]] = {}


@pytest.fixture(scope="module")
def corpus(tmp_path_factory: pytest.TempPathFactory) -> list[Any]:
    pytest.importorskip("xarray", reason="the `io` extra (xarray) is not installed")
    pytest.importorskip("h5netcdf", reason="the `io` extra (h5netcdf) is not installed")
    from hostile import file_corpus

    return file_corpus(tmp_path_factory.mktemp("corpus"))


def _read(reader: str, path: Any) -> tuple[str, Any, float]:
    """Calls `reader` on `path` in a daemon thread (a reader that blocks on a FIFO or reads
    /dev/zero for ever fails the test instead of hanging it); returns the outcome, the value
    or exception, and the seconds taken."""
    import threading
    import time

    from hostile import read_with

    box: dict[str, Any] = {}

    def run() -> None:
        start = time.perf_counter()
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", dz.InertiaWarning)
                box["value"] = ("ok", read_with(reader, path))
        except BaseException as exc:  # noqa: BLE001 - sorted by the test
            box["value"] = ("error", exc)
        box["seconds"] = time.perf_counter() - start

    thread = threading.Thread(target=run, daemon=True)
    thread.start()
    thread.join(30.0)
    assert not thread.is_alive(), f"{reader}({path}) blocked for 30 s"
    outcome, value = box["value"]
    return outcome, value, box["seconds"]


@pytest.mark.parametrize("reader", ["load", "read_aem", "load_scene", "Body.load"])
def test_every_reader_on_every_file(reader: str, corpus: list[Any]) -> None:
    """Each reader given every file of the corpus (see `hostile.file_corpus`): its own valid
    files return a result; every other file — each other format, cut short, grown past the
    bound, spoilt, a FIFO, /dev/zero, a folder, a missing path — ends in a ValueError subclass
    (the reader's documented one) naming the file, never another exception, a hang or a
    crash. Files that are no regular file, too large or of another format are refused before
    their content is read (at once: /dev/zero would never end)."""
    if reader == "Body.load":
        pytest.importorskip("trimesh", reason="the `mesh` extra (trimesh) is not installed")
    documented = {"load": dz.ReadError, "read_aem": dz.ReadError,
                  "load_scene": dz.SceneError, "Body.load": dz.MeshError}[reader]
    counts: Counter[str] = Counter()
    failures = []
    for item in corpus:
        outcome, value, seconds = _read(reader, item.path)
        if reader in item.valid_for:
            if outcome != "ok":
                failures.append(f"{item.name}: valid, but {type(value).__name__}: {value}")
            counts[f"{item.category}: result"] += 1
            continue
        if outcome == "ok":
            failures.append(f"{item.name} ({item.category}): accepted, returned {value!r}")
            continue
        if not isinstance(value, documented):
            failures.append(f"{item.name} ({item.category}): {type(value).__name__} (not "
                            f"{documented.__name__}): {value}")
            continue
        if str(item.path) not in str(value) and item.path.name not in str(value):
            failures.append(f"{item.name}: the message does not name the file: {value}")
        up_front = item.category in ("special", "oversized")
        if up_front and seconds > 2.0:
            failures.append(f"{item.name}: refused after {seconds:.1f} s, not up front")
        counts[f"{item.category}: {'refused up front' if up_front else 'clear error'}"] += 1
    FILE_OUTCOMES[reader] = counts
    if path := os.environ.get("DZ_HOSTILE_REPORT"):
        try:
            with open(path, encoding="utf-8") as f:
                report = json.load(f)
        except (OSError, ValueError):
            report = {}
        report[f"files: {reader}"] = dict(counts)
        with open(path, "w", encoding="utf-8") as f:
            json.dump(report, f, indent=1, sort_keys=True)
    assert not failures, "\n".join(failures)
    assert sum(counts.values()) == len(corpus)
