"""`make stack`: the team stack as local processes. ``environment`` chooses ports and secrets once per stack
directory; ``supervisor`` runs deploy/stack/Procfile and restarts what dies."""
