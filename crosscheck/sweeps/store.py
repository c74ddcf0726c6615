"""A sweep's result store: one Parquet file per chunk, written atomically, and a manifest that knows what is finished.

Layout of a store directory::

    manifest.json                the spec (as read), its sha256, the versions (written once)
    chunks/chunk-000123.parquet  a finished chunk's table
    chunks/chunk-000123.json     its record: file, row count, sha256, seconds
    chunks/chunk-000123.failed.json   the error of a chunk that raised
    .lock                        held (flock) by the one process writing

Nothing half-written is ever read: a chunk is written to a temporary file in
the same directory, flushed, and renamed into place (atomic on POSIX); its
record, written the same way after that, is what makes it count as finished
(one small file per chunk, so a million-run sweep never rewrites a growing
manifest).  A chunk whose file is missing or whose checksum does not match
its record (a truncated or edited file) is not trusted: ``verified`` drops
it with a warning and the sweep recomputes it.
"""

from __future__ import annotations

import hashlib
import json
import os
import platform
import shutil
import warnings
from contextlib import contextmanager
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

from crosscheck.files import exclusive, sha256_file

__all__ = ["Store", "StoreError", "versions"]

FORMAT = 1


class StoreError(ValueError):
    """A store that cannot be used as asked (another writer, another spec, a damaged manifest)."""


def _write_atomic(path: Path, data: bytes) -> None:
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    with open(tmp, "wb") as f:
        f.write(data)
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)


def versions(engine: str | None = None) -> dict:
    """Versions of what computes a sweep of ``engine`` (recorded in the manifest): crosscheck, numpy, scipy, the
    engine's own libraries (none for the analytic reference or an unknown name) and the store's."""
    from crosscheck import engines
    from crosscheck.report.provenance import package_versions

    libs = engines.get(engine).libraries if engine in engines.names() else ()
    return package_versions(("crosscheck", "numpy", "scipy", *libs, "pyarrow", "dask", "distributed"))


def _now() -> str:
    return datetime.now(timezone.utc).isoformat(timespec="seconds")


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
        self.root.mkdir(parents=True, exist_ok=True)

        def refuse(holder: str) -> StoreError:
            return StoreError(f"out {str(self.root)!r} is being written by {holder or 'another process'}; wait for it or use another directory")

        with exclusive(self.root / ".lock", f"pid {os.getpid()} on {platform.node()}", refuse):
            yield self

    def read_manifest(self) -> dict | None:
        """The manifest with the chunk records as they are now (``chunks``: id -> record, ``failed``: id -> error); None if absent."""
        if not self.manifest_path.exists():
            return None
        try:
            m = json.loads(self.manifest_path.read_text())
        except (json.JSONDecodeError, UnicodeDecodeError) as e:
            raise StoreError(f"manifest {str(self.manifest_path)!r} is damaged ({e}); use --fresh to start the sweep again") from None
        missing = [k for k in ("format", "spec", "spec_sha256", "n_chunks") if not isinstance(m, dict) or k not in m]
        if missing:
            raise StoreError(f"manifest {str(self.manifest_path)!r} is damaged (no {', '.join(missing)}); use --fresh to start the sweep again")
        m["chunks"], m["failed"] = {}, {}
        if self.chunks.is_dir():
            for p in self.chunks.glob("chunk-*.json"):
                cid = str(int(p.name[6:12]))
                try:
                    rec = json.loads(p.read_text())
                except (json.JSONDecodeError, UnicodeDecodeError):
                    continue  # a damaged record: the chunk counts as not finished
                if not isinstance(rec, dict) or not (isinstance(rec.get("file"), str) and isinstance(rec.get("sha256"), str) or "error" in rec):
                    continue  # not a record this store wrote: the chunk counts as not finished
                if p.name.endswith(".failed.json"):
                    m["failed"][cid] = rec["error"]
                else:
                    m["chunks"][cid] = rec
        return m

    def _write_manifest(self, m: dict) -> None:
        body = {k: v for k, v in m.items() if k not in ("chunks", "failed")}  # those live in the chunk records
        body["updated"] = _now()
        _write_atomic(self.manifest_path, (json.dumps(body, indent=1, sort_keys=True, default=str) + "\n").encode())

    def open(self, spec, *, fresh: bool = False) -> dict:
        """The manifest for ``spec``: a new one, or the existing one if it is for the same spec.

        Raises StoreError when the directory holds another sweep (unless ``fresh``,
        which deletes its chunks first) or something that is not a store.
        """
        m = self.read_manifest() if not fresh else None
        if m is not None and m.get("spec_sha256") != spec.digest:
            raise StoreError(f"out {str(self.root)!r} holds a different sweep (spec sha256 {m.get('spec_sha256', '?')[:12]}, this one "
                             f"{spec.digest[:12]}); use --fresh to replace it or choose another directory")
        if m is None:
            if not fresh and self.root.exists() and any(p.name not in (".lock",) for p in self.root.iterdir()):
                raise StoreError(f"out {str(self.root)!r} is not empty and has no sweep manifest; use --fresh to replace its sweep or choose another directory")
            if self.chunks.exists():
                shutil.rmtree(self.chunks)
            if fresh and self.manifest_path.exists():
                self.manifest_path.unlink()
            m = {"format": FORMAT, "spec": spec.source, "spec_sha256": spec.digest, "engine": spec.engine, "n_runs": spec.n_runs,
                 "n_chunks": spec.n_chunks, "chunk": spec.chunk, "versions": versions(spec.engine), "created": _now(), "chunks": {}, "failed": {}}
        self.chunks.mkdir(parents=True, exist_ok=True)
        m["versions_resumed"] = versions(spec.engine) if m.get("chunks") else None
        self._write_manifest(m)
        return m

    def warnings(self) -> dict[str, int]:
        """The engine's warnings over the store's finished chunks, by kind (recorded by the process that computed each)."""
        total: dict[str, int] = {}
        for rec in (self.read_manifest() or {"chunks": {}})["chunks"].values():
            for k, n in (rec.get("warnings") or {}).items():
                total[k] = total.get(k, 0) + int(n)
        return total

    def verified(self, m: dict) -> set[int]:
        """Ids of the manifest's chunks whose file is present with its recorded sha256; the others are dropped with a warning."""
        ok = set()
        for cid, rec in list(m["chunks"].items()):
            path = self.chunks / rec["file"]
            if path.is_file() and sha256_file(path) == rec["sha256"]:
                ok.add(int(cid))
                continue
            warnings.warn(f"chunk {cid} of {str(self.root)!r} is {'missing' if not path.is_file() else 'damaged (sha256 mismatch)'}; "
                          "it will be recomputed", stacklevel=2)
            del m["chunks"][cid]
            (self.chunks / f"chunk-{int(cid):06d}.json").unlink(missing_ok=True)
            path.unlink(missing_ok=True)
        return ok

    def write_chunk(self, m: dict, chunk_id: int, columns: dict, seconds: float, *, warnings: dict | None = None) -> None:
        """Write chunk ``chunk_id``'s table atomically, then record it (file, rows, sha256) in the manifest."""
        import pyarrow as pa
        import pyarrow.parquet as pq

        name = f"chunk-{chunk_id:06d}.parquet"
        table = pa.table({k: pa.array(list(v) if np.asarray(v).dtype == object else np.asarray(v)) for k, v in columns.items()})
        buf = pa.BufferOutputStream()
        pq.write_table(table, buf)
        data = buf.getvalue().to_pybytes()  # hashed as written: no second read of the file
        _write_atomic(self.chunks / name, data)
        rec = {"file": name, "rows": table.num_rows, "sha256": hashlib.sha256(data).hexdigest(), "seconds": seconds, "warnings": dict(warnings or {})}
        _write_atomic(self.chunks / f"chunk-{chunk_id:06d}.json", json.dumps(rec).encode())
        (self.chunks / f"chunk-{chunk_id:06d}.failed.json").unlink(missing_ok=True)
        m["chunks"][str(chunk_id)] = rec
        m["failed"].pop(str(chunk_id), None)

    def record_failure(self, m: dict, chunk_id: int, error: str) -> None:
        _write_atomic(self.chunks / f"chunk-{chunk_id:06d}.failed.json", json.dumps({"error": error}).encode())
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
            raise StoreError(f"out {str(self.root)!r} has no sweep manifest (manifest.json); run crosscheck sweep into it first")
        missing = m["n_chunks"] - len(m["chunks"])
        if missing and not partial:
            raise StoreError(f"the sweep in {str(self.root)!r} is unfinished: {missing} of {m['n_chunks']} chunks missing; "
                             "re-run the same crosscheck sweep command to finish it")
        frames = []
        for cid in sorted(m["chunks"], key=int):
            rec = m["chunks"][cid]
            path = self.chunks / rec["file"]
            if not path.is_file() or sha256_file(path) != rec["sha256"]:
                raise StoreError(f"chunk {cid} of {str(self.root)!r} is missing or damaged (sha256 mismatch); re-run the sweep to recompute it")
            frames.append(pq.read_table(path).to_pandas())
        if not frames:
            return pd.DataFrame()
        return pd.concat(frames, ignore_index=True).sort_values("run", kind="stable").reset_index(drop=True)
