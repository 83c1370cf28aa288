"""phonglab.scene"""
