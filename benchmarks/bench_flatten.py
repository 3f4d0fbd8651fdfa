"""Flattening time of a chain of N planar links (revolute + rigid bar + body per link).

Prints the median of a few runs for N = 10, 100, 1000 and the time per link, which should stay
roughly constant (near-linear scaling). Usage: python benchmarks/bench_flatten.py [--quick]
"""
from __future__ import annotations

import statistics
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from compiler.flatten import flatten_model  # noqa: E402

COMPONENTS = """
component World
  frame_b = Frame2D()
relations
  frame_b.x = 0
  frame_b.y = 0
  frame_b.phi = 0
end

component Revolute
  frame_a = Frame2D()
  frame_b = Frame2D()
  variable phi::Angle
  variable w::AngularVelocity
relations
  frame_a.x = frame_b.x
  frame_a.y = frame_b.y
  frame_b.phi = frame_a.phi + phi
  w = der(phi)
  frame_a.fx + frame_b.fx = 0
  frame_a.fy + frame_b.fy = 0
  frame_a.tau = 0
  frame_b.tau = 0
end

component FixedTranslation
  frame_a = Frame2D()
  frame_b = Frame2D()
  parameter r::Real[2] = [1, 0]
  variable r0::Real[2]
relations
  r0 = [cos(frame_a.phi) -sin(frame_a.phi); sin(frame_a.phi) cos(frame_a.phi)] * r
  frame_b.x = frame_a.x + r0[1]
  frame_b.y = frame_a.y + r0[2]
  frame_b.phi = frame_a.phi
  frame_a.fx + frame_b.fx = 0
  frame_a.fy + frame_b.fy = 0
  frame_a.tau + frame_b.tau + r0[1] * frame_b.fy - r0[2] * frame_b.fx = 0
end

component Body
  frame_a = Frame2D()
  parameter m::Real = 1
  parameter I::Real = 0.1
  variable r::Real[2]
  variable v::Real[2]
  variable phi::Angle
  variable w::AngularVelocity
relations
  r = [frame_a.x, frame_a.y]
  v = der(r)
  m * der(v) = [frame_a.fx, frame_a.fy] + m * MultibodyComponents.PlanarMechanics.gravity_acceleration_2d()
  phi = frame_a.phi
  w = der(phi)
  I * der(w) = frame_a.tau
end

component Link
  frame_a = Frame2D()
  frame_b = Frame2D()
  parameter L::Real = 1
  joint = Revolute()
  bar = FixedTranslation(r = [L, 0])
  body = Body(m = L, I = L / 12)
relations
  connect(frame_a, joint.frame_a)
  connect(joint.frame_b, bar.frame_a)
  connect(bar.frame_b, body.frame_a, frame_b)
end

component Chain
  structural parameter n::Integer = 10
  world = World()
  links = [Link(L = 1 / i) for i in 1:n]
relations
  connect(world.frame_b, links[1].frame_a)
  for i in 1:n - 1
    connect(links[i].frame_b, links[i + 1].frame_a)
  end
end
"""


def bench(n: int, repeats: int, folder: Path) -> float:
    path = folder / f"Chain{n}.dyad"
    path.write_text(COMPONENTS.replace("integer = 10", f"Integer = {n}").replace(
        "n::Integer = 10", f"n::Integer = {n}"), encoding="utf-8")
    times = []
    for _ in range(repeats):
        began = time.perf_counter()
        flat = flatten_model(f"{path}:Chain")
        times.append(time.perf_counter() - began)
    assert len(flat.equations) == sum(1 for v in flat.variables)
    return statistics.median(times)


def main() -> None:
    quick = "--quick" in sys.argv
    sizes = (10, 100) if quick else (10, 100, 1000)
    with tempfile.TemporaryDirectory() as tmp:
        for n in sizes:
            repeats = 5 if n <= 100 else 3
            median = bench(n, repeats, Path(tmp))
            print(f"flatten chain N={n:5d}: median {median * 1e3:9.1f} ms   "
                  f"({median / n * 1e3:6.2f} ms per link)")


if __name__ == "__main__":
    main()
