"""phonglab.app"""
