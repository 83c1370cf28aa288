"""phonglab: an interactive teaching app for the Phong illumination model."""
