union() {
  cube([2, 1, 1]);
  translate([1, 0.5, 0]) cube([1, 2, 1.5]);
  translate([2, 0, 0]) cube([1, 1, 1]);
}
