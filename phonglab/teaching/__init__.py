"""phonglab.teaching"""
