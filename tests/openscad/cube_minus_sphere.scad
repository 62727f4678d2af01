difference() { cube(2, center = true); sphere(1.3, $fn = 96); }
