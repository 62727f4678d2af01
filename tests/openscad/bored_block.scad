difference() {
  cube([2, 2, 1]);
  translate([1, 1, -1]) cylinder(h = 3, r = 0.5, $fn = 96);
  translate([2, 2, 1]) sphere(0.6, $fn = 96);
}
