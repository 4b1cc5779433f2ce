"""Drawing the world into a frame's codes, one kind of scenery per module; compose orders them."""
