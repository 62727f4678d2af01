#!/usr/bin/env python3
"""Write a scene script of about N megabytes (default 10) for the parse benchmark:
a realistic mix of lets, functions, modules, comprehensions, blocks and long
numeric lists (the shape of real data such as the teapot's control points)."""
import random, sys

target = int(float(sys.argv[1]) * 1024 * 1024) if len(sys.argv) > 1 else 10 * 1024 * 1024
out = sys.stdout
rng = random.Random(1)
size = 0
i = 0
chunks = []
while size < target:
    pts = ", ".join("[%.4f, %.4f, %.4f]" % (rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(0, 3))
                    for _ in range(16))
    s = (f"// patch {i}\n"
         f"let p{i} = [{pts}];\n"
         f"fn f{i}(x, h = 0.2) = h * sin(x * 180) + (x > 0 ? x ^ 2 : -x) % 3;\n"
         f"let g{i} = [for (k = [0:15]) if (k % 2 == 0) p{i}[k] else each [k, k * 2]];\n"
         f"module m{i}(n, gap = 1.2) {{\n"
         f"  for (j = [0:n-1]) object {{ geometry bezier(p{i}); transform translate([j * gap, 0, 0]) * rotate([0, 0, {i % 360}]); style s{i % 7}; }}\n"
         f"}}\n"
         f"style s{i} {{ base #3a6ea5; shade toon {{ bands 3; threshold 0.5; }} lines {{ kinds silhouette, crease(40); width 2; color #141414; }} }}\n"
         f"let t{i} = let (a = {i}, b = a + 1) \"label \\u{{58a8}} {i}\";\n")
    chunks.append(s)
    size += len(s.encode())
    i += 1
out.write("".join(chunks))
