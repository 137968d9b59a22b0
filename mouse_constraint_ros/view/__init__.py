"""``mouse_view``: a live 3D view of the body in a web browser, and the mouse that drags it."""
