difference() {
  union() {
    cube([3, 1, 1]);
    mirror([1, 0, 0]) cube([1, 2, 1]);
  }
  translate([0.5, 0.5, 0.5]) intersection() {
    cube(1, center = true);
    rotate([45, 0, 0]) cube(1, center = true);
  }
}
