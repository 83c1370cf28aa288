"""phonglab.render"""
