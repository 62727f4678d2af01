difference() {
  cube(2);
  cube(1);
  translate([0, 0.75, 1.5]) cube([2, 0.5, 0.5]);
}
