"""Pictures of a simulation: the excavator dashboard (scene_plot), a generic side view of planar
multibody models (planar: what to draw, animate: the GIF), and the scene's output bundle."""
