"""The parameters of the compiled kernels as numpy records: ``PARAMS`` per run, ``BODY``
per body.

:data:`PARAMS` is the structured dtype that the CPU loops (:mod:`pde_rotor.kernels.cpu`),
the CUDA kernel (:mod:`pde_rotor.kernels.cuda`) and the compiled physics
(:mod:`pde_rotor.physics`) read by field name (numba compiles ``p.dt`` to a load of
the record's field on both targets); :func:`make_record` fills it from a run's objects
(:class:`~pde_rotor.model.setup.Setup`: the configuration, the rotor's shape, the scheme
and the stop schedule, made once there), :func:`make_body_records` the :data:`BODY`
records of its bodies.

Their fields that come from the config are derived from the schema, not listed here
(:mod:`pde_rotor.config.recorded`): every numeric key of the run's sections
:data:`PARAMS_SECTIONS` and of a body (:class:`pde_rotor.config.BodyConfig`, whose
:class:`~pde_rotor.config.BodyLoads` the rotor's ``rotor:`` section takes too) is the
field of its name with its value, or the field its marker names. A new numeric key
therefore reaches ``p.NAME`` (``b.NAME`` for a body's) with no edit of this module; what is
written here are the fields computed from several keys, from the time step, from the
scheme or from the bodies' shapes (:data:`BUILT_PARAMS`, :data:`BUILT_BODY`).

The fields, by the equation that uses them (Koyano et al., Chaos 2020):

* time and grid: ``dt`` (the step of the run), ``dx``;
* Eq. (eqc): ``diffusion`` D, ``evaporation`` a, ``source`` s0 / (pi rho^2);
* Eq. (eqv): ``flow`` (False: v = 0, Fig. 8), ``drag`` eta, ``bulk_drag`` eta_b,
  ``viscosity`` D_eta;
* Eqs. (torque), (eq_motion), (noiseav): ``tension_slope`` k, ``inv_saturation``
  1 / c_sat of the saturating law (0: linear, :mod:`pde_rotor.physics.tension`),
  ``torque_sign`` (+-1,
  ``rotor.torque``), ``inertia`` I, ``friction`` mu, ``kick`` sqrt(2 dt) sigma / I, and
  as for a body's record (the rotor is the ``fixed_axis`` body at the origin,
  :mod:`pde_rotor.physics.motion`) ``motion``, ``mass`` (0: it does not translate) and
  the external load ``external_force_x``, ``external_force_y`` (0) and ``external_torque``,
  and a track body's ``track_x``, ``track_y``, ``track_radius``, ``track_direction``,
  ``track_force`` (0: the rotor is not on a track);
* Eqs. (ejt0), (rc), (rj) and F, G: ``n_corners`` N, ``apothem`` R cos(pi/N),
  ``pill_radius`` rho, ``pill_distance`` R_c, ``asymmetry`` Delta, ``smoothing`` delta;
* the stop schedule in steps: ``n_ini``, ``n_stop``, ``n_period``, ``cycles``;
* the vessel whose walls a body may not cross (``grid.vessel``): ``vessel`` (0: the dish,
  1: an annulus, 2: a rectangle; :mod:`pde_rotor.physics.motion`), its centre
  ``vessel_x``, ``vessel_y`` and sizes ``vessel_a``, ``vessel_b`` (R1, R2 or the half
  widths; the dish's rim domain_radius - dx in ``vessel_b``);
* the contact between bodies and with the walls (``contact:``): ``contact_stiffness``
  kappa, ``contact_range`` ell (0: no contact), ``contact_damping`` gamma;
* the scheme (:mod:`pde_rotor.model.schemes`): ``contour`` (contour-form torque),
  ``tan_half`` tan(pi/N), ``window_lo``, ``window_hi`` (the spline window),
  ``taps_lo``, ``taps_hi`` (its part the contour's taps read), and for the
  filtered F and G of ``consistent`` (``filtered``) the layout of the filter tables:
  ``table_n``, ``table_x0``, ``table_inv_step`` (the plate's 2-D table),
  ``profile_inv_step`` (the pill profile), ``crease``, ``corner_end`` (where F_eps
  takes the table), ``edge_u0``, ``edge_inv_step``
  (the edge profile).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from functools import cache

import numpy as np
from pydantic import BaseModel

from ..config import BodyConfig, RotorConfig
from ..config.recorded import record_layout, record_values
from ..model.bodies import Body
from ..model.body_schemes import BodyScheme
from ..model.filtering import CREASE_WIDTHS
from ..model.pde import TORQUE_SIGN
from ..model.setup import Setup
from ..physics.motion import MOTION_FIXED_AXIS, VESSEL_ANNULUS, VESSEL_RECTANGLE

_F8, _I8, _B1 = "f8", "i8", "b1"

PARAMS_SECTIONS = ("geometry", "camphor", "flow", "rotor", "noise", "protocol", "grid")
"""The run's sections whose keys are fields of :data:`PARAMS` (with the rotor's body's,
:meth:`pde_rotor.config.RotorConfig.rotor_body`)."""

BUILT_PARAMS: tuple[tuple[str, str], ...] = (
    ("dt", _F8),
    ("source", _F8),
    ("torque_sign", _F8),
    ("kick", _F8),
    ("apothem", _F8),
    ("pill_distance", _F8),
    ("n_ini", _I8),
    ("n_stop", _I8),
    ("n_period", _I8),
    ("motion", _I8),
    ("mass", _F8),
    ("track_x", _F8),
    ("track_y", _F8),
    ("track_radius", _F8),
    ("track_direction", _F8),
    ("track_force", _F8),
    ("tan_half", _F8),
    ("window_lo", _I8),
    ("window_hi", _I8),
    ("taps_lo", _I8),
    ("taps_hi", _I8),
    ("table_n", _I8),
    ("table_x0", _F8),
    ("table_inv_step", _F8),
    ("profile_inv_step", _F8),
    ("crease", _F8),
    ("corner_end", _F8),
    ("edge_u0", _F8),
    ("edge_inv_step", _F8),
    ("vessel", _I8),
    ("vessel_x", _F8),
    ("vessel_y", _F8),
    ("vessel_a", _F8),
    ("vessel_b", _F8),
    ("contact_stiffness", _F8),
    ("contact_range", _F8),
    ("contact_damping", _F8),
    ("contour", _B1),
    ("filtered", _B1),
)
"""The fields of :data:`PARAMS` that :func:`make_record` computes (module docstring)."""


def _dtype(
    built: Sequence[tuple[str, str]],
    sections: Sequence[list[tuple[str, str]]],
    body: list[tuple[str, str]],
) -> np.dtype:
    """The record of the `built` fields, the config's `sections` and the `body` layout
    (:func:`pde_rotor.config.recorded.record_layout`). A body field that a section has
    with the same type is one field (the ``rotor:`` section's loads are its body's).

    Raises:
        TypeError: a config field named as a built one or as one of another section.
    """
    fields = dict(built)
    shared = {}
    for layout in (*sections, body):
        for name, kind in layout:
            if name in fields and shared.get(name) != kind:
                msg = (
                    f"the config's record field {name!r} ({kind}) is already a field of the "
                    f"record ({fields[name]}): rename the key or mark it "
                    "(pde_rotor/config/recorded.py)"
                )
                raise TypeError(msg)
            fields[name] = kind
            if layout is not body:
                shared[name] = kind
    return np.dtype(list(fields.items()), align=True)


@cache
def params_dtype(sections: tuple[type[BaseModel], ...], body: type[BaseModel]) -> np.dtype:
    """:data:`PARAMS` for the section classes of :data:`PARAMS_SECTIONS` and the body's class."""
    return _dtype(BUILT_PARAMS, [record_layout(cls) for cls in sections], record_layout(body))


PARAMS = params_dtype(
    tuple(RotorConfig.model_fields[name].annotation for name in PARAMS_SECTIONS), BodyConfig
)
"""The kernels' parameter record (fields: see the module docstring)."""


def make_record(setup: Setup) -> np.ndarray:
    """The kernels' parameters of one run as a record array of length 1.

    Args:
        setup: the run's objects (:class:`~pde_rotor.model.setup.Setup`): its
            configuration, rotor shape, scheme and stop schedule, at the time step the
            kernels take (the solver's; ``grid.dt`` by default, :meth:`Setup.at`).

    Returns:
        A (1,) array of dtype :data:`PARAMS`, which the CPU loops take (and read as
        ``params[0]``); the GPU stacks one per member.
    """
    config, scheme, dt = setup.config, setup.scheme, setup.dt
    body = config.rotor_body()
    sections = [getattr(config, name) for name in PARAMS_SECTIONS]
    rec = np.zeros(1, dtype=params_dtype(tuple(map(type, sections)), type(body)))
    for part in (body, *sections):
        for name, value in record_values(part).items():
            rec[name] = value
    rho = config.geometry.pill_radius
    rec["dt"] = dt
    rec["source"] = config.camphor.supply / (math.pi * rho**2)
    rec["torque_sign"] = TORQUE_SIGN[config.rotor.torque]
    rec["kick"] = config.kick_scale(dt)
    rec["apothem"] = setup.shape.apothem
    rec["pill_distance"] = config.geometry.pill_distance
    schedule = setup.schedule
    rec["n_ini"] = schedule.n_ini
    rec["n_stop"] = schedule.n_stop
    rec["n_period"] = schedule.n_period
    rec["motion"] = MOTION_FIXED_AXIS
    vessel = config.grid.vessel
    rec["vessel_x"], rec["vessel_y"] = config.grid.domain_centre
    rec["vessel_b"] = config.grid.domain_radius - config.grid.dx
    if config.contact.enabled:
        rec["contact_stiffness"] = config.contact.stiffness
        rec["contact_range"] = config.contact.range
        rec["contact_damping"] = config.contact.damping
    if vessel is not None:
        if vessel.shape == "annulus":
            rec["vessel"] = VESSEL_ANNULUS
            rec["vessel_a"], rec["vessel_b"] = vessel.inner_radius, vessel.outer_radius
        else:
            rec["vessel"] = VESSEL_RECTANGLE
            rec["vessel_a"], rec["vessel_b"] = vessel.half_widths
    rec["contour"] = scheme.contour
    rec["tan_half"] = scheme.tan_half
    rec["window_lo"], rec["window_hi"] = scheme.window
    rec["taps_lo"], rec["taps_hi"] = scheme.taps
    tables = scheme.tables
    if tables is not None:
        rec["filtered"] = True
        rec["table_n"] = tables.plate_n
        rec["table_x0"] = tables.plate_x0
        rec["table_inv_step"] = 1.0 / tables.plate_step
        rec["profile_inv_step"] = 1.0 / tables.pill_step
        rec["crease"] = CREASE_WIDTHS * tables.plate_reach / math.cos(math.atan(scheme.tan_half))
        rec["corner_end"] = tables.corner_end
        rec["edge_u0"] = tables.edge_u0
        rec["edge_inv_step"] = 1.0 / tables.edge_step
    return rec


BUILT_BODY: tuple[tuple[str, str], ...] = (
    ("plate", _I8),
    ("n_corners", _I8),
    ("size_a", _F8),
    ("size_b", _F8),
    ("reach", _F8),
    ("contact", _F8),
    ("pill_start", _I8),
    ("pill_count", _I8),
    ("motion", _I8),
    ("mass", _F8),
    ("inertia", _F8),
    ("friction", _F8),
    ("kick", _F8),
    ("n_ini", _I8),
    ("n_stop", _I8),
    ("n_period", _I8),
    ("cycles", _I8),
    ("track_x", _F8),
    ("track_y", _F8),
    ("track_radius", _F8),
    ("track_direction", _F8),
    ("track_force", _F8),
    ("spans", _I8),
    ("tan_half", _F8),
    ("crease", _F8),
    ("corner_end", _F8),
    ("f_start", _I8),
    ("f_count", _I8),
    ("table_start", _I8),
    ("table_n", _I8),
    ("table_m", _I8),
    ("table_x0", _F8),
    ("edge_start", _I8),
    ("edge_count", _I8),
    ("edge_u0", _F8),
    ("ring_start", _I8),
    ("ring_count", _I8),
    ("window_half", _I8),
)
"""The fields of :data:`BODY` that :func:`make_body_records` and :func:`make_body_tables`
compute (the rest: a body's own keys, :mod:`pde_rotor.config.recorded`)."""


@cache
def body_dtype(body: type[BaseModel]) -> np.dtype:
    """:data:`BODY` for the bodies' config class."""
    return _dtype(BUILT_BODY, [], record_layout(body))


BODY = body_dtype(BodyConfig)
"""One body of :func:`pde_rotor.kernels.bodies.advance_bodies`: plate kind
(:data:`pde_rotor.physics.indicators.PLATE_POLYGON`...), its corners and sizes (``size_a``:
apothem, radius or half length; ``size_b``: half width), the footprint radius ``reach``
(where it is drawn) and the contact radius ``contact`` (contact springs and walls),
its pills' range in the pill table, motion kind, m, I, mu, the noise kick
sqrt(2 dt) sigma / I, its stop schedule in steps, its external force and torque and, for
a ``track`` body, its track's centre, radius, direction of travel and tangential force,
and whether it spans the channel (``spans``: 1, its plate crossing the vessel's no-flux
walls, its integrals :func:`pde_rotor.kernels.body_sums.spanning_integrals`).
For the ``consistent`` scheme
(:func:`make_body_tables`): tan(pi/N), the crease width and the corner table's end
``corner_end`` of a polygon, where its
filtered tables lie in the flat arrays (a disk's F profile ``f_*``, a polygon's corner
table or a strip's quadrant table ``table_*``, ``table_n`` x ``table_m`` spline
coefficients, a polygon's edge profile ``edge_*``, a disk's radial rule ``ring_*``), and
the half side of its spline window.
"""


_PLATES = {"none": 0, "polygon": 1, "disk": 2, "strip": 3}
_MOTIONS = {"fixed": 0, "fixed_axis": 1, "free": 2, "track": 3}


def make_body_records(setup: Setup) -> tuple[np.ndarray, np.ndarray]:
    """The bodies of a run as the records of :func:`pde_rotor.kernels.bodies.advance_bodies`.

    Args:
        setup: the run's objects at the kernels' time step: its bodies, their stop
            schedules and the configuration (whose ``source`` scales the pills' densities).

    Returns:
        (body records of dtype :data:`BODY`, pills (P, 7): body-frame x, y, rho, the
        pill's source density s_j / (pi rho_j^2) relative to the run record's ``source``,
        the distance from X, its angle in the body frame, and 0).
    """
    config, bodies, dt = setup.config, setup.bodies, setup.dt
    dtype = body_dtype(type(bodies[0].config)) if bodies else BODY
    records = np.zeros(len(bodies), dtype=dtype)
    rows = []
    reference = config.camphor.supply / (math.pi * config.geometry.pill_radius**2)
    for k, (body, schedule) in enumerate(zip(bodies, setup.body_schedules, strict=True)):
        shape = body.shape
        rec = records[k]
        rec["plate"] = _PLATES[shape.plate]
        rec["n_corners"] = shape.n_corners
        if shape.plate == "polygon":
            rec["size_a"] = shape.apothem
        elif shape.plate == "disk":
            rec["size_a"] = shape.radius
        elif shape.plate == "strip":
            rec["size_a"], rec["size_b"] = shape.length / 2, shape.width / 2
        rec["reach"] = shape.reach
        rec["contact"] = shape.contact
        rec["pill_start"], rec["pill_count"] = len(rows), len(shape.pills)
        for x, y, rho, supply in shape.pills:
            density = supply / (math.pi * rho**2)
            rows.append([x, y, rho, density / reference, math.hypot(x, y), math.atan2(y, x), 0])
        rec["motion"] = _MOTIONS[body.motion]
        rec["mass"], rec["inertia"], rec["friction"] = body.mass, body.inertia, body.friction
        rec["kick"] = math.sqrt(2.0 * dt) * body.noise_sigma / body.inertia
        for name, value in record_values(body.config).items():
            rec[name] = value
        if body.track is not None:
            track = body.track
            rec["track_x"], rec["track_y"] = track.centre
            rec["track_radius"], rec["track_direction"] = track.radius, track.direction
            rec["track_force"] = track.force
            rec["spans"] = track.spans
        if schedule is not None:
            rec["n_ini"], rec["n_stop"] = schedule.n_ini, schedule.n_stop
            rec["n_period"], rec["cycles"] = schedule.n_period, schedule.cycles
        else:
            rec["n_period"] = 1
    return records, np.array(rows, dtype=float).reshape(-1, 7)


def make_body_tables(
    bodies: Sequence[Body], scheme: BodyScheme, records: np.ndarray, n: int
) -> tuple[np.ndarray, ...]:
    """The tables of the bodies' ``consistent`` scheme as the kernels read them.

    Fills the scheme's fields of `records` (:data:`BODY`) and returns the arrays of
    :func:`pde_rotor.kernels.bodies.advance_bodies`: (quad_s, quad_t, the radial
    profiles one after the other, per pill (P, 6) the start and length of its G profile,
    of its F profile and of its radial rule, the polygons' corner tables and the strips'
    quadrant tables (spline coefficients) one after the other, the polygons' edge
    profiles, the circles' radial rules (2, I) one after the other
    (:func:`~pde_rotor.model.body_schemes.ring_rule`), and scratch: the spline
    coefficients (n^2) and a line's carry (n)). Equal tables (the pills of one radius,
    bodies of one shape) are stored once, so that K equal bodies read one corner table
    (megabytes) from the caches, not K. For the ``paper`` scheme, one-element arrays of
    the same types.

    Args:
        bodies: the run's bodies.
        scheme: their scheme (:class:`~pde_rotor.model.body_schemes.BodyScheme`).
        records: the body records of :func:`make_body_records`, updated.
        n: cells along a side of the grid.
    """
    pill_count = sum(len(b.shape.pills) for b in bodies)
    pill_profiles = np.zeros((max(1, pill_count), 6), dtype=np.int64)
    if not scheme.consistent:
        one = np.zeros(1)
        rings = np.zeros((2, 1))
        return (scheme.quad_s, scheme.quad_t, one, pill_profiles, one, one, rings, one, one)
    profiles: list[np.ndarray] = []
    corners: list[np.ndarray] = []
    edges: list[np.ndarray] = []
    rings: list[np.ndarray] = []

    def append(parts: list[np.ndarray], array: np.ndarray) -> tuple[int, int]:
        start = 0
        for part in parts:  # an equal table already there is shared, not copied
            if part.shape == array.shape and np.array_equal(part, array):
                return start, array.shape[-1]
            start += part.shape[-1]
        parts.append(array)
        return start, array.shape[-1]

    m = 0
    for k, (body, filt) in enumerate(zip(bodies, scheme.filters, strict=True)):
        rec = records[k]
        shape = body.shape
        for j in range(len(shape.pills)):
            pill_profiles[m, :2] = append(profiles, filt.pill_g[j])
            if filt.pill_f:
                pill_profiles[m, 2:4] = append(profiles, filt.pill_f[j])
                pill_profiles[m, 4:] = append(rings, filt.rings[j])
            m += 1
        if filt.disk is not None:
            rec["f_start"], rec["f_count"] = append(profiles, filt.disk)
            rec["ring_start"], rec["ring_count"] = append(rings, filt.rings[0])
        tables = filt.polygon
        if tables is not None:
            tan_half = math.tan(math.pi / shape.n_corners)
            rec["tan_half"] = tan_half
            rec["crease"] = CREASE_WIDTHS * tables.plate_reach / math.cos(math.atan(tan_half))
            rec["corner_end"] = tables.corner_end
            rec["table_start"], _ = append(corners, tables.plate)
            rec["table_n"], rec["table_x0"] = tables.plate_n, tables.plate_x0
            rec["table_m"] = tables.plate_n
            rec["edge_start"], rec["edge_count"] = append(edges, tables.edge)
            rec["edge_u0"] = tables.edge_u0
        strip = filt.strip
        if strip is not None:
            rec["table_start"], _ = append(corners, strip.coef)
            rec["table_n"], rec["table_m"] = strip.rows, strip.columns
            rec["table_x0"] = strip.x0
        rec["window_half"] = scheme.window_half(shape, filt)
    flat = [np.concatenate(parts) if parts else np.zeros(1) for parts in (profiles, corners, edges)]
    return (
        scheme.quad_s,
        scheme.quad_t,
        flat[0],
        pill_profiles,
        flat[1],
        flat[2],
        np.ascontiguousarray(np.concatenate(rings, axis=1)) if rings else np.zeros((2, 1)),
        np.zeros(n * n),
        np.zeros(n),
    )
