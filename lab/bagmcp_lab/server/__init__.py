"""The Lab's HTTP side: a chat turn and benchmark runs for the /lab page, behind the gateway's routes."""
