"""The cases' geometry (every dimension the scenes, the points and the closed forms share) and
the closed forms: the illuminance each case must read, by formula or by quadrature."""
import math
import pathlib

ROOT = pathlib.Path(__file__).resolve().parents[3]
SCENES = ROOT / "testdata/cie171"

RADIANCE_EFFICACY = 179.0  # lm/W, Radiance's WHTEFFICACY: a .rad scene's lux
OPTICKS_EFFICACY = 683.0  # lm/W, a Mitsuba scene's lux (white light: the weights sum to 1)

# 5.2 point source
POINT_I = 1000.0  # cd
POINT_H = 3.0  # m above the floor's centre
FLOOR_HALF = 2.0  # the floor is 4 m × 4 m, centred on the origin, z = 0
POINT_XY = [(0, 0), (0.5, 0), (1, 0), (1.5, 0), (2, 0), (1, 1), (2, 1), (2, 2)]
RSPHERE = 0.01  # m, Radiance's stand-in for the point source

# 5.3 area sources
AREA_L = 1000.0  # cd/m²
AREA_H = 2.0  # m
RECT = (-1.0, 1.0, -0.5, 0.5)  # x0, x1, y0, y1: 2 m × 1 m
RECT_XY = [(0, 0), (0.5, 0.25), (1, 0.5), (1, 0), (0, 0.5), (1.5, 0), (2, 0), (0, 2), (1.5, 1.5), (2, 2)]
DISC_R = 0.5  # m
DISC_XY = [(0, 0), (0.25, 0), (0.5, 0), (0.5, 0.5), (1, 0), (2, 0), (1.5, 1.5), (2, 2)]

# 5.7 internal obstructions: 5.3's rectangle over the floor, an opaque black rectangle between
OBST_RECT = (0.1, 0.7, -0.3, 0.9)  # x0, x1, y0, y1 of the occluder
OBST_H = 1.2  # m: the occluder's height (the source's is AREA_H)
OBST_XY = [(0, 0), (0.5, 0), (-0.5, 0), (1, 0), (0.8, 0.6), (0.3, -0.5), (-1, -1), (1.5, 0.5), (-1.5, 0)]

# 5.4 / 5.6 closed box
BOX_SIDE = 3.0  # m: x, y in [-1.5, 1.5], z in [0, 3]; the source at its centre
BOX_I = 1000.0  # cd
BOX_RHOS = [0.0, 0.5, 0.8, 0.95]
BOX_PATHS = "1M"  # a path of the ρ = 0.95 box has ~20 vertices: 1 M paths is a 1 GB dataset
BOX_WALLS = ["floor", "ceiling", "wall_xm", "wall_xp", "wall_ym", "wall_yp"]
RSPHERE_BOX = 0.005  # m: Radiance's source sphere absorbs what hits it (6·10⁻⁵ of each bounce at 0.95)
GL_ORDER = 6  # Gauss-Legendre points per side for Radiance's mean over the floor

# 5.5 directional transmittance of clear glass: a horizontal pane over a black floor, a parallel
# source at incidence θ (in the x-z plane, from −x)
PANE_EN = 1000.0  # lux: the source's normal illuminance
PANE_H = 1.0  # m: the pane's height over the floor
PANE_HALF = 20.0  # m: the pane and the floor are 40 m x 40 m (at 85° a point sees the pane 11.4 m away)
PANE_ANGLES = [0, 15, 30, 45, 60, 70, 80, 85]  # degrees of incidence
PANE_XY = [(0, 0.5), (-1, 1), (0.5, 2)]  # y > x: off the line y = x of the pane's shared edge (docs/validation-cie171.md says why)
SUN_ANGLE = 0.533  # degrees: Radiance's stand-in for the parallel source is a `source` of this diameter

# 5.9–5.12 sky component: a closed black room x, y ∈ [−ROOM_HALF, ROOM_HALF], z ∈ [0, ROOM_H]
ROOM_HALF = 3.0
ROOM_H = 3.0
SKY_LZ = 1000.0  # cd/m²: the uniform sky's luminance, the overcast sky's zenith luminance
ROOF_OPENING = (-1.0, 1.0, -0.5, 0.5)  # x0, x1, y0, y1 at z = ROOM_H
ROOF_XY = [(0, 0), (0.5, 0.25), (1, 0.5), (1, 0), (0, 0.5), (2, 0), (0, 2), (2, 2)]
FACADE_OPENING = (-1.0, 1.0, 1.0, 2.0)  # x0, x1, z0, z1 in the north wall y = ROOM_HALF
FACADE_XY = [(0, 2), (0, 1), (0, 0), (1, 1), (-1, 2), (2, 0), (0, -2), (-2, -2)]
GLASS_N = 1.52  # the pane's index (Radiance's glass default), transmissivity 1
DAYLIGHT_FIXED = "256"  # a fixed `measure --direct-samples`, beside the default (auto)
GENSKY_GROUND = 0.2 * 0.777778  # gensky -c's ground brightness over the zenith's (ρ = 0.2)
# 5.13 / 5.14 external obstructions (opaque black, outside the room), each parallel to its opening
ROOF_MASK = (0.0, 2.0, -2.0, 2.0, ROOM_H + 0.5)  # x0, x1, y0, y1, z: a panel over half the roof opening
FACADE_OBST = (0.5, 8.0, ROOM_HALF + 2.0, 3.5)  # x0, x1, y, height: a building 2 m in front of the façade


# ---------------------------------------------------------------- closed forms


def e_point(x, y, i=POINT_I, h=POINT_H):
    """E (lux) at (x, y, 0) from an isotropic point source of i cd at (0, 0, h): I cos³θ / h²."""
    d2 = x * x + y * y + h * h
    return i * h / d2**1.5


def corner(x, y, h):
    """π × the configuration factor from a point to a parallel rectangle [0, x] × [0, y] at height
    h (signed x, y: the formula is odd in each), so that E = L × corner(...)."""
    X, Y = x / h, y / h
    sx, sy = math.sqrt(1 + X * X), math.sqrt(1 + Y * Y)
    return 0.5 * (X / sx * math.atan(Y / sx) + Y / sy * math.atan(X / sy))


def e_rect(px, py, lum=AREA_L, h=AREA_H, rect=RECT):
    """E (lux) at (px, py, 0) under a Lambertian rectangle of luminance lum at height h, by
    superposition of the four corner rectangles."""
    x0, x1, y0, y1 = rect
    return lum * (corner(x1 - px, y1 - py, h) - corner(x0 - px, y1 - py, h)
                  - corner(x1 - px, y0 - py, h) + corner(x0 - px, y0 - py, h))


def hidden_rect(px, py, occluder=OBST_RECT, h_o=OBST_H, h=AREA_H, rect=RECT):
    """The part of the source rectangle that the occluder (parallel, at height h_o) hides from
    the floor point (px, py): the occluder's central projection from the point onto the source's
    plane (scaled by h / h_o about the point) intersected with the source; None if empty."""
    k = h / h_o
    x0, x1, y0, y1 = occluder
    px0, px1, py0, py1 = px + (x0 - px) * k, px + (x1 - px) * k, py + (y0 - py) * k, py + (y1 - py) * k
    rx0, rx1, ry0, ry1 = rect
    ix0, ix1, iy0, iy1 = max(rx0, px0), min(rx1, px1), max(ry0, py0), min(ry1, py1)
    return (ix0, ix1, iy0, iy1) if ix0 < ix1 and iy0 < iy1 else None


def e_obstructed(px, py):
    """E (lux) at (px, py, 0) under 5.3's rectangle with the occluder between: the whole source's
    less its hidden part's (superposition: E is additive over the source's area)."""
    hidden = hidden_rect(px, py)
    return e_rect(px, py) - (e_rect(px, py, rect=hidden) if hidden else 0.0)


def e_disc(px, py, lum=AREA_L, h=AREA_H, r=DISC_R):
    """E (lux) at (px, py, 0) under a Lambertian disc of radius r centred above the origin at
    height h: π L × ½ [1 − (h² + a² − r²) / √((h² + a² + r²)² − 4 a² r²)], a the offset;
    π L r² / (h² + r²) on the axis."""
    a2 = px * px + py * py
    return math.pi * lum * 0.5 * (1 - (h * h + a2 - r * r) / math.sqrt((h * h + a2 + r * r) ** 2 - 4 * a2 * r * r))


def e_box(rho, i=BOX_I, side=BOX_SIDE):
    """Mean irradiance (lux) of the walls of a closed cube with a source of Φ = 4π i lm inside:
    Φ / (A (1 − ρ)), A = 6 side²."""
    return 4 * math.pi * i / (6 * side * side * (1 - rho))


def e_reflected(rho, i=BOX_I, side=BOX_SIDE):
    """5.8: the internally reflected component's mean over the closed box's walls,
    ρ Φ / (A (1 − ρ)) (the mean irradiance less the direct component's Φ / A)."""
    return rho * e_box(rho, i, side)


def perp_corner(x, z, c):
    """π × the configuration factor from a point of the floor (normal up) to the rectangle
    [0, x] × [0, z] of a wall at distance c, its corner at the foot of the perpendicular from the
    point to the wall: ½ [atan X − atan(X/√(1+Z²))/√(1+Z²)], X = x/c, Z = z/c (Lambert's polygon
    formula over the rectangle's four edges; odd in x, z ≥ 0), so that E = L × perp_corner(...)."""
    X, Z = x / c, z / c
    s = math.sqrt(1 + Z * Z)
    return 0.5 * (math.atan(X) - math.atan(X / s) / s)


def e_roof_uniform(px, py, lum=SKY_LZ, opening=ROOF_OPENING, h=ROOM_H):
    """E (lux) at (px, py, 0) under a uniform sky of luminance lum seen through the roof opening:
    L × the parallel rectangle's π × configuration factor (the area source's closed form)."""
    return e_rect(px, py, lum, h, opening)


def e_facade_uniform(px, py, lum=SKY_LZ, opening=FACADE_OPENING, wall=ROOM_HALF):
    """E (lux) at (px, py, 0) under a uniform sky seen through the opening [x0, x1] × [z0, z1] of
    the wall y = wall: the perpendicular rectangle's corners by superposition."""
    x0, x1, z0, z1 = opening
    c = wall - py
    return lum * (perp_corner(x1 - px, z1, c) - perp_corner(x0 - px, z1, c)
                  - perp_corner(x1 - px, z0, c) + perp_corner(x0 - px, z0, c))


def sky_uniform(dz):
    return 1.0


def sky_cie_overcast(dz):
    """Moon and Spencer's CIE standard overcast sky over its zenith: (1 + 2 cos θ)/3."""
    return (1 + 2 * dz) / 3


def sky_gensky_overcast(dz):
    """gensky -c's sky over its zenith (skybright.cal): the CIE overcast (1 + 2 dz)/3 blended
    toward the ground's brightness ρ·7/9 (ρ = 0.2) by the weights (dz + 1.01)^±10."""
    ws, wg = (dz + 1.01) ** 10, (dz + 1.01) ** -10
    return (ws * sky_cie_overcast(dz) + wg * GENSKY_GROUND) / (ws + wg)


def fresnel_rs_rp(cos_i, n=GLASS_N):
    """The s and p reflectances of an air-to-glass interface."""
    sin2_t = (1 - cos_i * cos_i) / (n * n)
    cos_t = math.sqrt(1 - sin2_t)
    rs = (cos_i - n * cos_t) / (cos_i + n * cos_t)
    rp = (n * cos_i - cos_t) / (n * cos_i + cos_t)
    return rs * rs, rp * rp


def t_pane_opticks(cos_i):
    """Opticks's `glass` of transmissivity 1 (core ThinDielectric): T = 1 − 2r/(1 + r) =
    (1 − r)/(1 + r), r the unpolarised Fresnel reflectance."""
    r = sum(fresnel_rs_rp(cos_i)) / 2
    return (1 - r) / (1 + r)


def t_pane_radiance(cos_i):
    """Radiance's `glass` of transmissivity 1: the same slab sum per polarisation, averaged."""
    return sum((1 - r) / (1 + r) for r in fresnel_rs_rp(cos_i)) / 2


def no_pane(cos_i):
    return 1.0


def e_pane(theta_deg, pane=t_pane_opticks, en=PANE_EN):
    """E (lux) at a point of the floor (normal up) behind the horizontal pane, from a parallel
    source of normal illuminance en at incidence theta_deg: E_n cos θ T(θ) (the pane is parallel
    to the floor: the angle of incidence on the pane is the point's)."""
    c = math.cos(math.radians(theta_deg))
    return en * c * pane(c)


def t_cie_clear_6mm(cos_i):
    """The directional transmittance of 6 mm clear glass as a polynomial in cos θ (Tregenza and
    Sharples's algorithm 2.34, which CIE 171's glazed cases are reported to use): for comparison
    only, a glass of its own thickness and absorption, not the pane here."""
    c = cos_i
    return -0.028378 + c * (3.156075 + c * (-3.058376 + c * (-1.428919 + c * (4.014235 - 1.775827 * c))))


def gl01(n):
    """Gauss-Legendre nodes and weights on [0, 1]."""
    x, w = gauss_legendre(n)
    return [(0.5 * (a + 1), 0.5 * b) for a, b in zip(x, w)]


def opening_rect(kind):
    """The opening as (corner, edge u, edge v, unit normal)."""
    if kind == "roof":
        x0, x1, y0, y1 = ROOF_OPENING
        return (x0, y0, ROOM_H), (x1 - x0, 0, 0), (0, y1 - y0, 0), (0, 0, 1)
    x0, x1, z0, z1 = FACADE_OPENING
    return (x0, ROOM_HALF, z0), (x1 - x0, 0, 0), (0, 0, z1 - z0), (0, 1, 0)


def e_quadrature(px, py, kind, sky, pane=no_pane, order=48, lum=SKY_LZ):
    """E (lux) at (px, py, 0), normal up, from the sky seen through the opening `kind`:
    ∫ L(dz) T(cos θ_w) cos θ_p cos θ_w / r² dA over the opening (Gauss-Legendre, order² points)."""
    (ox, oy, oz), u, v, nw = opening_rect(kind)
    area = math.sqrt(sum(c * c for c in u)) * math.sqrt(sum(c * c for c in v))
    nodes = gl01(order)
    total = 0.0
    for a, wa in nodes:
        for b, wb in nodes:
            dx = ox + a * u[0] + b * v[0] - px
            dy = oy + a * u[1] + b * v[1] - py
            dz = oz + a * u[2] + b * v[2]
            r2 = dx * dx + dy * dy + dz * dz
            r = math.sqrt(r2)
            cos_w = abs(dx * nw[0] + dy * nw[1] + dz * nw[2]) / r
            total += wa * wb * sky(dz / r) * pane(cos_w) * (dz / r) * cos_w / r2
    return lum * area * total


def e_quad_rect(px, py, kind, rect, sky, order=48, lum=SKY_LZ):
    """As e_quadrature over the part rect = (a0, a1, b0, b1) of the opening's plane (roof: x, y;
    façade: x, z); 0 when empty."""
    a0, a1, b0, b1 = rect
    if a1 <= a0 or b1 <= b0:
        return 0.0
    nodes = gl01(order)
    total = 0.0
    for a, wa in nodes:
        for b, wb in nodes:
            x, w = a0 + a * (a1 - a0), b0 + b * (b1 - b0)
            dx, dy, dz = (x - px, w - py, ROOM_H) if kind == "roof" else (x - px, ROOM_HALF - py, w)
            r2 = dx * dx + dy * dy + dz * dz
            r = math.sqrt(r2)
            cos_w = (dz if kind == "roof" else dy) / r
            total += wa * wb * sky(dz / r) * (dz / r) * cos_w / r2
    return lum * (a1 - a0) * (b1 - b0) * total


def hidden_part(px, py, kind):
    """The part of the opening the external obstruction hides from (px, py, 0): its central
    projection onto the opening's (parallel) plane, an axis-aligned rectangle, ∩ the opening."""
    if kind == "roof":
        x0, x1, y0, y1, z = ROOF_MASK
        t = ROOM_H / z
        ox0, ox1, oy0, oy1 = ROOF_OPENING
        return (max(ox0, px + (x0 - px) * t), min(ox1, px + (x1 - px) * t),
                max(oy0, py + (y0 - py) * t), min(oy1, py + (y1 - py) * t))
    x0, x1, y, height = FACADE_OBST
    t = (ROOM_HALF - py) / (y - py)
    ox0, ox1, oz0, oz1 = FACADE_OPENING
    return (max(ox0, px + (x0 - px) * t), min(ox1, px + (x1 - px) * t), oz0, min(oz1, height * t))


def e_obstructed_sky(px, py, kind, sky=None, order=48):
    """E (lux) through the opening `kind` with its external obstruction: the opening's sky
    component less the hidden part's, both by the quadrature (gensky's overcast sky)."""
    sky = sky or sky_gensky_overcast
    x0, x1, y0, y1 = ROOF_OPENING if kind == "roof" else FACADE_OPENING
    return (e_quad_rect(px, py, kind, (x0, x1, y0, y1), sky, order)
            - e_quad_rect(px, py, kind, hidden_part(px, py, kind), sky, order))


def check_quadrature():
    """The closed forms against the quadrature, and the quadrature's convergence: the largest
    relative differences (closed forms vs order 48; order 48 vs 96 for the overcast sky and the
    pane)."""
    closed = max(max(abs(e_roof_uniform(x, y) / e_quadrature(x, y, "roof", sky_uniform) - 1) for x, y in ROOF_XY),
                 max(abs(e_facade_uniform(x, y) / e_quadrature(x, y, "facade", sky_uniform) - 1)
                     for x, y in FACADE_XY))
    conv = max(abs(e_quadrature(x, y, k, sky_gensky_overcast, t_pane_opticks)
                   / e_quadrature(x, y, k, sky_gensky_overcast, t_pane_opticks, order=96) - 1)
               for k, pts in (("roof", ROOF_XY), ("facade", FACADE_XY)) for x, y in pts)
    return closed, conv



def gauss_legendre(n):
    """Nodes and weights on [-1, 1] (Newton on the Legendre polynomial)."""
    nodes, weights = [], []
    for k in range(1, n + 1):
        x = math.cos(math.pi * (k - 0.25) / (n + 0.5))
        for _ in range(100):
            p0, p1 = 1.0, x
            for j in range(2, n + 1):
                p0, p1 = p1, ((2 * j - 1) * x * p1 - (j - 1) * p0) / j
            dp = n * (x * p1 - p0) / (x * x - 1)
            dx = p1 / dp
            x -= dx
            if abs(dx) < 1e-15:
                break
        nodes.append(x)
        weights.append(2 / ((1 - x * x) * dp * dp))
    return nodes, weights


def box_floor_points():
    """Gauss-Legendre points of the floor (x, y, weight): Radiance's area mean is Σ w E / Σ w."""
    nodes, weights = gauss_legendre(GL_ORDER)
    s = BOX_SIDE / 2
    return [(s * a, s * b, wa * wb) for a, wa in zip(nodes, weights) for b, wb in zip(nodes, weights)]
