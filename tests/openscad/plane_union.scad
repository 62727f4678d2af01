difference() {
  linear_extrude(height = 1) union() {
    square([2, 1]);
    intersection() {
      translate([1, 0]) circle(1, $fn = 32);
      square([3, 3]);
    }
  }
  translate([0.5, 0.25, 0.5]) cube([0.5, 0.5, 1]);
}
