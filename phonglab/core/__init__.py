"""phonglab.core"""
