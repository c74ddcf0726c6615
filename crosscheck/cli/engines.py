"""``crosscheck engines [--json]``: every engine the registry finds, where it comes from and whether it can run here."""

from __future__ import annotations

import json

from crosscheck import engines

__all__ = ["register", "listing"]


def _version(lib: str) -> str | None:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version(lib)
    except PackageNotFoundError:
        return None


def _studies(spec) -> list[str]:
    """The studies an engine declares: its maps, convergence, ladder and interventions."""
    plan = spec.report
    out = []
    if plan is not None and plan.maps is not None:
        out.append("maps")
    if plan is not None and plan.convergence is not None:
        out.append("convergence")
    if spec.ladder:
        out.append("ladder")
    if spec.interventions:
        out.append("interventions")
    return out


def listing() -> dict:
    """{"engines": [one dict per engine], "broken": [one line per plugin that failed to load]} (nothing imported but
    the declarations: a library's version is read from its distribution's metadata)."""
    rows = []
    for spec in engines.specs():
        libs = [{"name": lib, "version": _version(lib)} for lib in spec.libraries]
        rows.append(
            {
                "name": spec.name,
                "label": spec.label,
                "origin": spec.origin,
                "libraries": libs,
                "installed": all(lib["version"] for lib in libs),
                "install": None if all(lib["version"] for lib in libs) else spec.pip_line(),
                "tags": sorted(spec.tags),
                "studies": _studies(spec),
            }
        )
    return {"engines": rows, "broken": sorted(engines.broken().values())}


def _text(data: dict) -> str:
    lines = []
    for e in data["engines"]:
        libs = ", ".join(f"{lib['name']} {lib['version'] or 'not installed'}" for lib in e["libraries"]) or "-"
        studies = ", ".join(e["studies"]) or "-"
        lines.append(f"{e['name']:<18} {e['label']}  [{e['origin']}]")
        lines.append(f"{'':<18} library: {libs}" + ("" if e["installed"] else f"  (install: {e['install']})"))
        lines.append(f"{'':<18} tags: {', '.join(e['tags']) or '-'}; studies: {studies}")
    lines.extend(data["broken"])
    return "\n".join(lines)


def _run(args) -> int:
    data = listing()
    print(json.dumps(data, indent=2) if args.json else _text(data))
    return 0


def register(sub) -> None:
    p = sub.add_parser(
        "engines",
        help="list every contact engine (built in and installed plugins): origin, library and version, tags, studies",
    )
    p.add_argument("--json", action="store_true", help="print the list as JSON")
    p.set_defaults(func=_run)
