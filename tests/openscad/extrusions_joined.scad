difference() {
  union() {
    linear_extrude(height = 2, twist = 15, scale = 0.5, slices = 3) square(1.2, center = true);
    rotate_extrude($fn = 32) translate([0.8, 0]) square([0.3, 0.4]);
  }
  translate([0, 0, 1.5]) cube([2, 0.3, 1], center = true);
}
