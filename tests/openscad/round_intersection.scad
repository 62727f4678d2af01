difference() {
  intersection() { sphere(1, $fn = 96); cube(1.5, center = true); }
  rotate([0, 90, 0]) cylinder(h = 3, r = 0.3, center = true, $fn = 96);
}
