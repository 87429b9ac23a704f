"""An example of your own methods for usvtool (docs/your-method.md): :mod:`.apf`, a controller,
and :mod:`.de`, a route planner, found by usvtool through this distribution's entry points."""
