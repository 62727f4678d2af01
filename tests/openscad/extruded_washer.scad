linear_extrude(height = 0.5) difference() {
  square(2, center = true);
  circle(0.6, $fn = 48);
}
