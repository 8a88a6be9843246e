"""The builder's kit's bill of materials: every fastener, key and spacer of the assembly with
quantities added up (:func:`fastener_lines`, :func:`fastener_rows`), and the parts to cut or turn
with their masses (:func:`made_rows`)."""

from __future__ import annotations

from typing import Any

import shapely

from qsm.embodiment.kit import base as bs
from qsm.embodiment.kit import fasteners as fs
from qsm.embodiment.kit import joints as jt
from qsm.realization.kit.moving_parts import solid_props


def screw_lines(name: str, qty: int, where: str) -> list[tuple[str, int, str]]:
    """The lines of ``qty`` screws ``name``; a threaded rod (DIN 976-1) brings a nut for the end
    a screw's head would be (its washer is counted with the head's)."""
    lines = [(name, qty, where)]
    if name.startswith("DIN 976-1"):
        lines.append((f"ISO 10511 {name.split()[2]}", qty, f"{where}: rod ends"))
    return lines


def _pin_lines(pins: dict[str, Any]) -> list[tuple[str, int, str]]:
    """Each pin's screw (or made pin), spacer, the spacers that fill its shoulder, washer and
    nut."""
    lines: list[tuple[str, int, str]] = []
    for j, pin in pins.items():
        thread = pin["nut"].split()[-1]
        lines += [
            (pin["screw"] or f"made: {pin['made']}", 1, f"pin {j}"),
            (
                pin["spacer"],
                pin["spacers"] + pin["fill_spacers"],
                f"between the plates at {j}, and filling its shoulder",
            ),
            (f"ISO 7089 {thread}", 1, f"under the nut at {j}"),
            (pin["nut"], 1, f"{j}"),
        ]
        if pin["shim"]:
            lines.append((pin["shim"], 1, f"closing the axial float at {j}"))
    return lines


def _hub_lines(hub: dict[str, Any], iface: Any) -> list[tuple[str, int, str]]:
    """A hub's screws to its link (with washers: from the link's far face into the hub's
    tapped flange, or from the hub's side into heat-set inserts) and its drive's key and set
    screw, or flange screws."""
    k, screws = hub["motor"], hub["link_screws"]
    lines: list[tuple[str, int, str]] = []
    if screws["screw"]:
        th = screws["thread"]
        lines += screw_lines(screws["screw"], jt.HUB_SCREWS, f"hub {k} to the {hub['link']}")
        lines.append((f"ISO 7089 {th}", jt.HUB_SCREWS, f"hub {k}: under the heads"))
        if screws["side"] == "hub":
            lines.append(
                (
                    f"{screws['insert']} heat-set insert",
                    jt.HUB_SCREWS,
                    f"hub {k}: in the {hub['link']}, from the hub's side",
                )
            )
    if iface.output == "shaft":
        key = hub["key"]
        name = f"DIN 6885 A {key['w_mm']:g} x {key['h_mm']:g} x {key['length_mm']:g}"
        lines.append((name, 1, f"drive {k} to hub {k}"))
        lines.append((hub["set_screw"], 1, f"hub {k} on drive {k}'s shaft"))
    else:
        lines += screw_lines(
            hub["flange_screw"], iface.flange_bolts, f"hub {k} to drive {k}'s output flange"
        )
    return lines


def fastener_lines(
    pins: dict[str, Any],
    hubs: list[dict[str, Any]],
    cheeks: list[dict[str, Any]],
    drives: list[dict[str, Any]],
    flange: dict[str, Any],
    table: dict[str, Any],
) -> list[tuple[str, int, str]]:
    """(order line, quantity, where) of every fastener, key and washer of the assembly."""
    lines = _pin_lines(pins)
    for hub, drive, c in zip(hubs, drives, cheeks, strict=True):
        k, iface = hub["motor"], drive["interface"]
        lines += _hub_lines(hub, iface)
        mount = fs.cap_screw(iface.mount_thread, c["pocket"]["web_mm"], True, "")
        lines += screw_lines(mount.name, iface.mount_bolts, f"drive {k} to cheek {k}")
        if c["fixing"]["screw"]:
            th = c["fixing"]["screw"].split()[2]
            lines += screw_lines(c["fixing"]["screw"], 3, f"cheek {k} to the base plate")
            lines += [(f"ISO 7089 {th}", 3, f"cheek {k}: under the heads")]
    lines += screw_lines(table["screw"], 4, "base plate to the table")
    lines += [("ISO 7089 M8", 4, "base plate: under the heads")]
    if flange.get("pattern"):
        lines += screw_lines(flange["centre_screw"], 1, "tool flange to the upper arm")
        lines += [("ISO 7089 M8", 1, "tool flange: under the head")]
    return lines


def fastener_rows(lines: list[tuple[str, int, str]]) -> list[dict[str, Any]]:
    """BOM rows of ``lines``, one per order line, quantities added across the assembly."""
    merged: dict[str, dict[str, Any]] = {}
    for name, qty, where in lines:
        row = merged.setdefault(
            name,
            {
                "item": name,
                "category": _category(name),
                "where": [],
                "quantity": 0,
                "designation": name,
            },
        )
        row["quantity"] += qty
        row["where"].append(f"{where} ({qty})")
    for row in merged.values():
        row["where"] = "; ".join(row["where"])
        row["material"] = _fastener_material(row["item"])
    return list(merged.values())


def _category(name: str) -> str:
    if name.startswith("made"):
        return "made part"
    if name.endswith("insert"):
        return "insert"
    return "key" if name.startswith("DIN 6885") else "fastener"


def _fastener_material(name: str) -> str:
    standard = " ".join(name.split()[:2])
    if standard.startswith("Ruthex"):
        return "brass"
    return {
        "ISO 4762": "steel 8.8",
        "ISO 7379": "steel 12.9",
        "ISO 7089": "steel 200 HV",
        "ISO 10511": "steel 8, nylon insert",
        "DIN 6885": "C45+C",
        "DIN 976-1": "steel 8.8",
    }.get(standard, "steel")


def _plate_mass_kg(plate: dict[str, Any], density: float) -> float:
    """Mass (kg) of a placed plate: its outline less its holes times its thickness, less a
    cheek's pocket (about its origin)."""
    poly = shapely.Polygon(plate["outline"], plate["holes"])
    volume = poly.area * plate["thickness_mm"]
    pocket = plate.get("pocket") or {}
    if pocket.get("depth_mm", 0.0) > 0:
        disc = shapely.Point(0, 0).buffer(pocket["d_mm"] / 2, 64)
        volume -= poly.intersection(disc).area * pocket["depth_mm"]
    return volume * density * 1e-9


def made_rows(geometry: dict[str, Any]) -> list[dict[str, Any]]:
    """BOM rows of the parts to cut or turn: the cheeks and base plate (aluminium, from their
    DXF), the hubs and the tool flange's disc (steel)."""
    al = bs.ALUMINIUM
    rows = []
    for name in ("cheek_1", "cheek_2", "base_plate"):
        plate = geometry["plates"][name]
        x0, y0, x1, y1 = shapely.Polygon(plate["outline"]).bounds
        rows.append(
            {
                "item": name.replace("_", " "),
                "category": "cut part",
                "where": "base",
                "quantity": 1,
                "material": al["name"],
                "mass_kg": _plate_mass_kg(plate, al["density_kg_m3"]),
                "bbox_x_mm": round(x1 - x0, 1),
                "bbox_y_mm": round(y1 - y0, 1),
                "bbox_z_mm": plate["thickness_mm"],
                "source": al["source"],
                "notes": f"cut from kit/dxf/{name}.dxf",
            }
        )
    for name, c in geometry["turned"].items():
        if name.startswith("drive"):
            continue
        rows.append(
            {
                "item": name.replace("_", " "),
                "category": "turned part",
                "where": "A" if name.startswith("hub") else "E",
                "quantity": 1,
                "material": "C45+N steel",
                "mass_kg": solid_props(c, (0.0, 0.0)).mass_kg,
                "bbox_x_mm": c["d_mm"],
                "bbox_y_mm": c["d_mm"],
                "bbox_z_mm": round(c["length_mm"], 1),
                "notes": f"kit/step/{name}.step",
            }
        )
    return rows
