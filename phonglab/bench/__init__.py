"""phonglab.bench"""
