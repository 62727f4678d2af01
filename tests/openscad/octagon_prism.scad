intersection() {
  cube([2, 2, 1], center = true);
  rotate([0, 0, 45]) cube([2, 2, 1], center = true);
}
