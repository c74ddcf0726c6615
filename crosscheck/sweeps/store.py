"""A sweep's result store: one Parquet file per chunk, written atomically, and a manifest that knows what is finished.

Layout of a store directory::

    manifest.json                the spec (as read), its sha256, the versions (written once)
    chunks/chunk-000123.parquet  a finished chunk's table
    chunks/chunk-000123.json     its record: file, row count, sha256, seconds, the versions that computed it
    chunks/chunk-000123.failed.json   the error of a chunk that raised
    .lock                        held (flock) by the one process writing

Nothing half-written is ever read: a chunk is written to a temporary file in
the same directory, flushed, and renamed into place (atomic on POSIX); its
record, written the same way after that, is what makes it count as finished
(one small file per chunk, so a million-run sweep never rewrites a growing
manifest).  A full disk is one ``StoreError`` naming the directory and the
bytes it needed, and leaves no temporary file.

Nothing edited is trusted either.  The manifest carries the sha256 of its own
content and must agree with itself (``n_chunks`` is ``n_runs`` over
``chunk``).  A chunk record names its id's own file, this sweep's spec
sha256 and its row count, so a copied, edited or foreign record is damaged.
A chunk whose record is damaged, or whose file is missing or does not match
its record's checksum (a truncated or edited file), is named in a warning and
recomputed by the next sweep (``verified``); ``load`` also checks that each
table holds exactly its chunk's runs.  A damaged or missing manifest is
rebuilt by re-running the same sweep, which keeps every chunk whose record
proves it belongs to that spec.  Files in ``chunks`` that are not the store's
(``chunk-1.json``) are named and left alone.

Nothing computed by other versions is mixed in.  The manifest records the
versions of what computes the sweep (crosscheck, numpy, scipy, the engine's
libraries); a store with finished chunks resumed under other versions is one
``StoreError`` naming each package and both versions (``--fresh`` recomputes
it).  Each chunk record carries its versions too, so a chunk kept through a
rebuilt manifest is recomputed if other versions computed it.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import platform
import re
import warnings
from contextlib import ExitStack, contextmanager
from datetime import UTC, datetime
from pathlib import Path

import numpy as np

from crosscheck.files import StoreError, sha256_file, store_error, write_atomic
from crosscheck.locking import exclusive
from crosscheck.versions import package_versions

__all__ = ["Store", "StoreError", "versions", "computing_versions", "FORMATS"]

#: The manifest's format: 2 seals the manifest with its own sha256 and records the spec's sha256 in each chunk
#: record; 1 (neither) is still read.
FORMAT = 2
FORMATS = (1, 2)

#: The names of the store's own files in ``chunks``: a chunk's table, its record, its failure, their temporary files.
#: A chunk id as ``f"{id:06d}"`` writes it: six digits, or more without a leading zero (chunk 1000000 and on).
_ID = r"(\d{6}|[1-9]\d{6,})"
_RECORD = re.compile(rf"^chunk-{_ID}\.json$")
_FAILED = re.compile(rf"^chunk-{_ID}\.failed\.json$")
_OWN = re.compile(rf"^(chunk-{_ID}\.(parquet|json|failed\.json)|\.chunk-{_ID}\.(parquet|json|failed\.json)\.tmp-\d+)$")
_SHA256 = re.compile(r"^[0-9a-f]{64}$")

_REBUILD = "re-run the same crosscheck sweep command to rebuild it (its intact chunks are kept)"


def _chunk_id(name: str) -> int:
    """The chunk id in the name of one of the store's chunk records (``chunk-000123.json``, ``chunk-1000000.json``)."""
    return int((_RECORD.match(name) or _FAILED.match(name)).group(1))


def _seal(body: dict) -> str:
    """sha256 of a manifest's content (its own seal and its time of writing aside)."""
    rest = {k: v for k, v in body.items() if k not in ("sha256", "updated")}
    return hashlib.sha256(json.dumps(rest, sort_keys=True, default=str).encode()).hexdigest()


def _manifest_problem(m) -> str | None:
    """Why ``m`` is not a manifest this store wrote (None if it is one)."""
    missing = [k for k in ("format", "spec", "spec_sha256", "n_chunks") if not isinstance(m, dict) or k not in m]
    if missing:
        return f"no {', '.join(missing)}"
    if m["format"] not in FORMATS or isinstance(m["format"], bool):
        return f"format {m['format']!r}, expected one of {', '.join(map(str, FORMATS))}"
    if "sha256" in m or m["format"] >= 2:
        if m.get("sha256") != _seal(m):
            return "its content differs from its sha256: edited after it was written"
    if not isinstance(m["spec"], dict) or not (isinstance(m["spec_sha256"], str) and _SHA256.match(m["spec_sha256"])):
        return "no spec or spec sha256"
    counts = [m.get(k) for k in ("n_chunks", "n_runs", "chunk")]
    if not all(isinstance(v, int) and not isinstance(v, bool) and v >= 1 for v in counts):
        return f"n_chunks, n_runs and chunk must be integers >= 1; got {', '.join(repr(v) for v in counts)}"
    n_chunks, n_runs, chunk = counts
    if n_chunks != math.ceil(n_runs / chunk):
        return f"n_chunks {n_chunks} is not n_runs {n_runs} in chunks of {chunk}"
    return None


def versions(engine: str | None = None) -> dict:
    """Versions of what computes a sweep of ``engine`` (recorded in the manifest): crosscheck, numpy, scipy, the
    engine's own libraries (none for the analytic reference or an unknown name) and the store's."""
    from crosscheck import engines

    libs = engines.get(engine).libraries if engine in engines.names() else ()
    return package_versions(("crosscheck", "numpy", "scipy", *libs, "pyarrow", "dask", "distributed"))


#: Packages of ``versions`` that only store or schedule a sweep: another version of one cannot move a result.
_STORING = ("pyarrow", "dask", "distributed")


def computing_versions(recorded) -> dict | None:
    """The versions among ``recorded`` (a ``versions`` dict) that a sweep's numbers depend on; None if it is not one."""
    if not isinstance(recorded, dict):
        return None
    return {k: v for k, v in recorded.items() if k not in _STORING}


def _version_change(recorded, now: dict) -> str:
    """How the computing versions ``recorded`` with a store's chunks differ from ``now`` ("" if they do not)."""
    before, after = computing_versions(recorded), computing_versions(now)
    if before is None:
        return "versions that its manifest does not record"
    return ", ".join(
        f"{k} {before.get(k) or 'absent'} (now {after.get(k) or 'absent'})"
        for k in sorted(set(before) | set(after))
        if before.get(k) != after.get(k)
    )


def import_libraries() -> None:
    """Import what writing and reading a chunk needs (pyarrow's Parquet and dataset modules, pandas).

    Each is imported at a store's first chunk otherwise: once in every forked process that writes one, which in the
    report's sections, each forked from one process, was 3 s of the quick report's 62 s of section CPU.
    """
    import pandas  # noqa: F401
    import pyarrow.dataset
    import pyarrow.parquet  # noqa: F401


def _now() -> str:
    return datetime.now(UTC).isoformat(timespec="seconds")


class Store:
    """The result store in directory ``root`` (see the module docstring)."""

    def __init__(self, root: str | Path):
        self.root = Path(root)
        self.chunks = self.root / "chunks"
        self.manifest_path = self.root / "manifest.json"

    # ------------------------------------------------------------- writer ---
    @contextmanager
    def writer(self):
        """Hold the store's lock while writing; ``StoreError`` at once if another process holds it."""

        def refuse(holder: str) -> StoreError:
            return StoreError(
                f"out {str(self.root)!r} is being written by {holder or 'another process'}; wait for it or use another directory"
            )

        stack = ExitStack()
        try:
            self.root.mkdir(parents=True, exist_ok=True)
            stack.enter_context(exclusive(self.root / ".lock", f"pid {os.getpid()} on {platform.node()}", refuse))
        except OSError as e:
            raise store_error(self.root / ".lock", e, 4096) from None  # the message names self.root
        with stack:
            yield self

    def _chunks_dir_problem(self) -> str | None:
        if self.chunks.exists() and not self.chunks.is_dir():
            return f"{str(self.chunks)!r} is not a directory"
        return None

    def read_manifest(self) -> dict | None:
        """The manifest with the chunk records as they are now; None if absent.

        ``chunks``: id -> record, ``failed``: id -> error, ``damaged``: record file name -> why it is not
        trusted (its chunk counts as not finished), ``stray``: names in ``chunks`` that are not the store's.
        Raises ``StoreError`` naming a damaged manifest.
        """
        try:
            if not self.manifest_path.exists():
                return None
            text = self.manifest_path.read_bytes().decode()
            m = json.loads(text)
        except (json.JSONDecodeError, UnicodeDecodeError) as e:
            raise StoreError(self._damaged_manifest(str(e))) from None
        except OSError as e:
            raise StoreError(f"manifest {str(self.manifest_path)!r} cannot be read ({e.strerror or e})") from None
        problem = _manifest_problem(m)
        if problem:
            raise StoreError(self._damaged_manifest(problem))
        problem = self._chunks_dir_problem()
        if problem:
            raise StoreError(f"out {str(self.root)!r} is damaged: {problem}; use --fresh to start the sweep again")
        m["chunks"], m["failed"], m["damaged"], m["stray"] = {}, {}, {}, []
        if self.chunks.is_dir():
            for p in sorted(self.chunks.iterdir()):
                rec, failed = _RECORD.match(p.name), _FAILED.match(p.name)
                if not _OWN.match(p.name):
                    m["stray"].append(p.name)
                if not (rec or failed):
                    continue
                cid = int((rec or failed).group(1))
                why = self._record_problem(m, p, cid, failed is not None)
                if isinstance(why, str):
                    m["damaged"][p.name] = why
                elif failed:
                    m["failed"][str(cid)] = why["error"]
                else:
                    m["chunks"][str(cid)] = why
        return m

    def _damaged_manifest(self, why: str) -> str:
        return f"manifest {str(self.manifest_path)!r} is damaged ({why}); {_REBUILD}"

    def _record_problem(self, m: dict, path: Path, cid: int, failed: bool) -> dict | str:
        """The record at ``path`` of chunk ``cid`` if this store wrote it for this sweep, or why not."""
        if cid >= m["n_chunks"]:
            return f"chunk {cid} is past the sweep's last chunk {m['n_chunks'] - 1}"
        try:
            rec = json.loads(path.read_bytes().decode())
        except (OSError, UnicodeDecodeError, json.JSONDecodeError) as e:
            return f"not readable JSON ({e})"
        if failed:
            return rec if isinstance(rec, dict) and isinstance(rec.get("error"), str) else "not a failure record"
        if not isinstance(rec, dict):
            return f"a JSON {type(rec).__name__}, expected an object"
        want = f"chunk-{cid:06d}.parquet"
        if rec.get("file") != want:
            return f"names the file {rec.get('file')!r}, not {want!r} (copied or edited)"
        if not (isinstance(rec.get("sha256"), str) and _SHA256.match(rec["sha256"])):
            return "no sha256 of its file"
        rows = min(m["chunk"], m["n_runs"] - cid * m["chunk"])
        if rec.get("rows") != rows or isinstance(rec.get("rows"), bool):
            return f"{rec.get('rows')!r} rows, chunk {cid} has {rows}"
        if "spec_sha256" in rec and rec["spec_sha256"] != m["spec_sha256"]:
            return "written for another sweep (its spec sha256 differs)"
        if "computed_with" in rec:
            other = _version_change(rec["computed_with"], m.get("versions") or {})
            if other:
                return f"computed with {other}"
        return rec

    def _write_manifest(self, m: dict) -> None:
        body = {
            k: v for k, v in m.items() if k not in ("chunks", "failed", "damaged", "stray")
        }  # those live in the chunk records
        body["format"] = FORMAT
        body["updated"] = _now()
        body = json.loads(json.dumps(body, default=str))  # sealed as it will be read back
        body["sha256"] = _seal(body)
        write_atomic(
            self.manifest_path,
            (json.dumps(body, indent=1, sort_keys=True, default=str) + "\n").encode(),
            sync=True,
            error=store_error,
        )

    def open(self, spec, *, fresh: bool = False) -> dict:
        """The manifest for ``spec``: a new one, or the existing one if it is for the same spec.

        Raises StoreError when the directory holds another sweep (unless ``fresh``,
        which deletes its chunks first) or something that is not a store.  A damaged
        or missing manifest of a store (its ``chunks`` directory present) is rebuilt
        from ``spec`` with a warning; the chunks whose records carry ``spec``'s sha256
        are kept (``verified`` checks their files).
        """
        m, rebuilt = None, None
        if not fresh:
            try:
                m = self.read_manifest()
            except StoreError as e:
                if not self._is_store():
                    if self.manifest_path.is_file() and not self._manifest_is_ours():
                        raise StoreError(self._not_ours()) from None
                    raise
                rebuilt = str(e).split(f"; {_REBUILD}")[0]
            if m is None and rebuilt is None and self._is_store() and self.chunks.is_dir():
                rebuilt = f"manifest {str(self.manifest_path)!r} is missing"
        if m is not None and m.get("spec_sha256") != spec.digest:
            raise StoreError(
                f"out {str(self.root)!r} holds a different sweep (spec sha256 {m.get('spec_sha256', '?')[:12]}, this one "
                f"{spec.digest[:12]}); use --fresh to replace it or choose another directory"
            )
        if m is None:
            if rebuilt is None and not self._owned():
                raise StoreError(self._not_ours())
            if rebuilt is None:
                self._delete_own_files()
            m = {
                "format": FORMAT,
                "spec": spec.source,
                "spec_sha256": spec.digest,
                "engine": spec.engine,
                "n_runs": spec.n_runs,
                "n_chunks": spec.n_chunks,
                "chunk": spec.chunk,
                "versions": versions(spec.engine),
                # every run of a sweep is of the scaled rod (m = l = g = 1) at its alpha: its numbers are scaled units
                "rod": {"mass": 1.0, "length": 1.0, "gravity": 1.0, "alpha": list(spec.alpha)},
                "caveats": list(spec.caveats),  # what the outcomes do not say (a horizon shorter than the window)
                "created": _now(),
                "chunks": {},
                "failed": {},
            }
            if rebuilt is not None:
                other = self._other_sweep(spec.digest)
                if (
                    other
                ):  # only records naming this spec prove their chunks are of it; the others are not ours to delete
                    raise StoreError(
                        f"{rebuilt}, and {other} was not recorded for this spec; use --fresh to replace that sweep "
                        "or choose another directory"
                    )
                self.manifest_path.unlink(missing_ok=True)
                self._write_manifest(m)
                m = self.read_manifest()
                kept = len(m["chunks"])
                warnings.warn(
                    f"{rebuilt}; rebuilt from the spec, keeping the {kept} chunks recorded for it", stacklevel=2
                )
        try:
            self.chunks.mkdir(parents=True, exist_ok=True)
        except OSError as e:
            raise store_error(self.chunks, e, 4096) from None  # the message names self.root
        now = versions(spec.engine)
        if m.get("chunks"):
            # chunks of other versions mixed with new ones would be a sweep that no one set of versions computes
            other = _version_change(m.get("versions"), now)
            if other:
                raise StoreError(
                    f"out {str(self.root)!r} holds {len(m['chunks'])} chunks computed with {other}; finishing the sweep "
                    "would mix the results of two versions: use --fresh to recompute it, or finish it with the versions "
                    "it was started with"
                )
        else:
            m["versions"] = now  # nothing computed yet: the sweep is this installation's
        m["versions_resumed"] = now if m.get("chunks") else None
        self._write_manifest(m)
        return m

    def _owned(self) -> bool:
        """Whether ``root`` is empty (its lock aside), a store (``_is_store``) or holds a manifest a store wrote
        (a JSON object with its format and spec sha256, sealed or not): only then may it be (re)written."""
        if not self.root.exists():
            return True
        if not self.root.is_dir():
            return False
        return all(p.name == ".lock" for p in self.root.iterdir()) or self._is_store() or self._manifest_is_ours()

    def _not_ours(self) -> str:
        return (
            f"out must be a directory that is empty or a sweep store crosscheck wrote; {str(self.root)!r} holds no "
            "manifest.json of its own: choose another directory (nothing in it is deleted, with or without --fresh)"
        )

    def _manifest_is_ours(self) -> bool:
        """Whether ``manifest.json`` is a JSON object with a store's format and spec sha256 (sealed or not)."""
        try:
            m = json.loads(self.manifest_path.read_bytes().decode())
        except (OSError, UnicodeDecodeError, ValueError):
            return False
        return isinstance(m, dict) and "format" in m and "spec_sha256" in m

    def _delete_own_files(self) -> None:
        """Delete the store's own files (a fresh start): its manifest and, in ``chunks``, the names it writes (``_OWN``);
        anything else there is someone else's and stays."""
        if self.chunks.is_dir():
            for p in self.chunks.iterdir():
                if _OWN.match(p.name) and p.is_file():
                    p.unlink()
        elif self.chunks.exists() and self._manifest_is_ours():
            self.chunks.unlink()  # the store's own name in a directory its manifest proves is the store's
        elif self.chunks.exists():
            raise StoreError(
                f"out must be a directory that is empty or a sweep store crosscheck wrote; {str(self.root)!r} holds a "
                "file 'chunks' where the store's chunks go, which crosscheck does not delete: choose another directory"
            )
        self.manifest_path.unlink(missing_ok=True)

    def _other_sweep(self, digest: str) -> str | None:
        """The first chunk record in ``chunks`` (readable, a table's record) that does not carry the spec sha256 ``digest``."""
        for p in sorted(self.chunks.glob("chunk-*.json")):
            if not _RECORD.match(p.name):
                continue
            try:
                rec = json.loads(p.read_bytes().decode())
            except (OSError, UnicodeDecodeError, json.JSONDecodeError):
                continue  # damaged: dropped with a warning by ``verified``
            if isinstance(rec, dict) and rec.get("spec_sha256") != digest:
                return f"chunk record {p.name}"
        return None

    def _is_store(self) -> bool:
        """Whether ``root`` holds only what a store writes (a damaged or missing manifest may then be rebuilt)."""
        if not self.root.is_dir() or self._chunks_dir_problem():
            return False
        names = {p.name for p in self.root.iterdir()}
        only_ours = "chunks" in names and all(
            n in ("chunks", "manifest.json", ".lock") or n.startswith(".manifest.json.tmp-") for n in names
        )
        # and something proves it: a manifest.json or chunks of nobody else's (a web app's chunks/ and manifest.json)
        return only_ours and (self._manifest_is_ours() or any(_OWN.match(p.name) for p in self.chunks.iterdir()))

    def warnings(self) -> dict[str, int]:
        """The engine's warnings over the store's finished chunks, by kind (recorded by the process that computed each)."""
        total: dict[str, int] = {}
        for rec in (self.read_manifest() or {"chunks": {}})["chunks"].values():
            for k, n in (rec.get("warnings") or {}).items():
                total[k] = total.get(k, 0) + int(n)
        return total

    def verified(self, m: dict) -> set[int]:
        """Ids of the manifest's chunks whose file is present with its recorded sha256; the others, and every damaged
        record, are named in a warning and dropped (their chunks are recomputed); stray files are named and left alone."""
        for name in m.get("stray", ()):
            warnings.warn(f"{str(self.chunks / name)!r} is not a file of the sweep store; it is ignored", stacklevel=2)
        for name, why in list(m.get("damaged", {}).items()):
            cid = _chunk_id(name)
            warnings.warn(
                f"chunk {cid} of {str(self.root)!r} has a damaged record {name} ({why}); it will be recomputed",
                stacklevel=2,
            )
            (self.chunks / name).unlink(missing_ok=True)
            if str(cid) not in m["chunks"]:
                (self.chunks / f"chunk-{cid:06d}.parquet").unlink(missing_ok=True)
        ok = set()
        for cid, rec in list(m["chunks"].items()):
            path = self.chunks / rec["file"]
            if path.is_file() and sha256_file(path) == rec["sha256"]:
                ok.add(int(cid))
                continue
            warnings.warn(
                f"chunk {cid} of {str(self.root)!r} is {'missing' if not path.is_file() else 'damaged (sha256 mismatch)'}; "
                "it will be recomputed",
                stacklevel=2,
            )
            del m["chunks"][cid]
            (self.chunks / f"chunk-{int(cid):06d}.json").unlink(missing_ok=True)
            path.unlink(missing_ok=True)
        return ok

    def write_chunk(
        self, m: dict, chunk_id: int, columns: dict, seconds: float, *, warnings: dict | None = None
    ) -> None:
        """Write chunk ``chunk_id``'s table atomically, then record it (file, rows, sha256) in the manifest."""
        import pyarrow as pa
        import pyarrow.parquet as pq

        name = f"chunk-{chunk_id:06d}.parquet"
        table = pa.table(
            {k: pa.array(list(v) if np.asarray(v).dtype == object else np.asarray(v)) for k, v in columns.items()}
        )
        buf = pa.BufferOutputStream()
        pq.write_table(table, buf)
        data = buf.getvalue().to_pybytes()  # hashed as written: no second read of the file
        write_atomic(self.chunks / name, data, sync=True, error=store_error)
        rec = {
            "file": name,
            "rows": table.num_rows,
            "sha256": hashlib.sha256(data).hexdigest(),
            "spec_sha256": m["spec_sha256"],
            "seconds": seconds,
            "warnings": dict(warnings or {}),
            "computed_with": computing_versions(m["versions"]),
        }
        write_atomic(self.chunks / f"chunk-{chunk_id:06d}.json", json.dumps(rec).encode(), sync=True, error=store_error)
        (self.chunks / f"chunk-{chunk_id:06d}.failed.json").unlink(missing_ok=True)
        m["chunks"][str(chunk_id)] = rec
        m["failed"].pop(str(chunk_id), None)

    def record_failure(self, m: dict, chunk_id: int, error: str) -> None:
        write_atomic(
            self.chunks / f"chunk-{chunk_id:06d}.failed.json",
            json.dumps({"error": error}).encode(),
            sync=True,
            error=store_error,
        )
        m["failed"][str(chunk_id)] = error

    # ------------------------------------------------------------- reader ---
    def load(self, *, partial: bool = False):
        """Every finished chunk as one ``pandas.DataFrame`` in run order; each file checked against its sha256 first.

        Raises StoreError for a directory without a manifest, a damaged chunk,
        or (unless ``partial``) a sweep with chunks still missing.
        """
        import pandas as pd
        import pyarrow.parquet as pq

        m = self.read_manifest()
        if m is None:
            raise StoreError(
                f"out {str(self.root)!r} has no sweep manifest (manifest.json); run crosscheck sweep into it first"
            )
        if m["damaged"] and not partial:
            name, why = next(iter(m["damaged"].items()))
            raise StoreError(
                f"chunk {_chunk_id(name)} of {str(self.root)!r} has a damaged record {name} ({why}); "
                "re-run the same crosscheck sweep command to recompute it"
            )
        missing = m["n_chunks"] - len(m["chunks"])
        if missing and not partial:
            raise StoreError(
                f"the sweep in {str(self.root)!r} is unfinished: {missing} of {m['n_chunks']} chunks missing; "
                "re-run the same crosscheck sweep command to finish it"
            )
        frames = []
        for cid in sorted(m["chunks"], key=int):
            rec = m["chunks"][cid]
            path = self.chunks / rec["file"]
            if not path.is_file() or sha256_file(path) != rec["sha256"]:
                raise StoreError(
                    f"chunk {cid} of {str(self.root)!r} is missing or damaged (sha256 mismatch); re-run the sweep to recompute it"
                )
            df = pq.read_table(path).to_pandas()
            lo = int(cid) * m["chunk"]
            if not (
                "run" in df
                and "chunk" in df
                and df["run"].tolist() == list(range(lo, lo + rec["rows"]))
                and (df["chunk"] == int(cid)).all()
            ):
                raise StoreError(
                    f"chunk {cid} of {str(self.root)!r} is damaged (its table does not hold runs {lo} to {lo + rec['rows'] - 1}); "
                    "re-run the sweep to recompute it"
                )
            frames.append(df)
        if not frames:
            return pd.DataFrame()
        return pd.concat(frames, ignore_index=True).sort_values("run", kind="stable").reset_index(drop=True)
