difference() {
  translate([-1, -3, 0]) cube([30, 14, 2]);
  translate([0, 0, 1]) linear_extrude(height = 2) text("CSG", size = 8, font = "DejaVu Sans", $fn = 32);
}
