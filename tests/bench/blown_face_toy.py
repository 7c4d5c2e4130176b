"""Benchmark (not a test): why a large crank step seals a blown face that finer steps keep
blown (docs/performance.md, "Step-size bistability"). A toy of the full zone at the leading
edge of a face whose other side is at a higher gas pressure: its width w grows by the Couette
inflow and shrinks by the pressure-driven outflow back through the edge,

    dw/dt = U/2 - K/w,   K = h^2 dp / (12 eta),

with an unstable equilibrium at w* = 2K/U (wider: it seals the face; narrower: it empties and
the face stays blown) whose growth rate there is lambda = U/(2 w*). From w0 = 0.9 w* the exact
zone empties. One backward-Euler step of dt (the film's time scheme) solves
w1 - dt (U/2 - K/w1) = w0: from 0.9 w* it has no root for 0.47 < lambda dt < 1.73 (only the
empty zone solves the step) and roots above w* from lambda dt = 1.73 on, so the step seals the
face. lambda dt = U dt / (2 w*): the ring's travel in a step against twice the zone's critical
width.

    python3 tests/bench/blown_face_toy.py
"""

from __future__ import annotations

import math


def exact(w0: float, u: float, k: float, dt: float, n: int = 20000) -> float:
    """The zone's width after dt (explicit Euler in n small steps; the zone cannot go below 0)."""
    w = w0
    h = dt / n
    for _ in range(n):
        if w <= 0.0:
            return 0.0
        w = max(w + h * (u / 2 - k / w), 0.0)
    return w


def backward_euler(w0: float, u: float, k: float, dt: float) -> list[float]:
    """The positive roots of one backward-Euler step (none: only the empty zone solves it)."""
    b = w0 + dt * u / 2
    disc = b * b - 4 * dt * k
    if disc < 0:
        return []
    return [(b + math.sqrt(disc)) / 2, (b - math.sqrt(disc)) / 2]


def main() -> None:
    u, k = 1.0, 0.1
    w_star = 2 * k / u
    lam = u / (2 * w_star)
    print("lambda dt  exact w(dt)/w*  backward-Euler roots / w*")
    for lam_dt in (0.25, 0.5, 1.0, 1.5, 2.0, 4.0, 8.0):
        dt = lam_dt / lam
        w0 = 0.9 * w_star
        roots = [round(r / w_star, 3) for r in backward_euler(w0, u, k, dt)]
        print(f"{lam_dt:9.2f}  {exact(w0, u, k, dt) / w_star:14.3f}  {roots}")


if __name__ == "__main__":
    main()
