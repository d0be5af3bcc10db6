#!/usr/bin/env bash
# Opens the dialog of a filter in a running MeshLab 2020.09 GUI by its name, through MeshLab's filter
# search (Ctrl+F, type the name, Down, Return: no menu positions), and waits until the dialog is there.
# For the screenshots and the GUI tests: MeshLab under Xvfb with no window manager, so the main window
# is given the keyboard focus first. Usage (DISPLAY set): gui-open-filter.sh "Tree Mesh from Point Cloud"
# Prints where the dialog's buttons are: "APPLY_X APPLY_Y CLOSE_X CLOSE_Y".
set -euo pipefail
filter=${1:?usage: gui-open-filter.sh FILTER_NAME}
main=""
# Up to two minutes: on a busy machine (the suite runs two tests at a time, some of them heavy)
# MeshLab once took more than the 30 s this waited before to show its window.
for i in $(seq 240); do
  main=$(xdotool search --onlyvisible --name "MeshLab 2020" 2>/dev/null | head -n 1) || true
  [ -n "$main" ] && break; sleep 0.5
done
[ -n "$main" ] || { echo "gui-open-filter: no MeshLab window" >&2; exit 1; }
sleep 3                                        # let it finish loading the layer
pattern=$(printf '%s' "$filter" | sed 's/[][().*^$+?{}|\\]/\\&/g')
# On a loaded machine the search can open later than the typing starts: then it is closed with
# Escape and tried again, three times in all.
for attempt in 1 2 3; do
  eval "$(xdotool getwindowgeometry --shell "$main")"   # X Y WIDTH HEIGHT
  xdotool mousemove $((X + WIDTH / 2)) $((Y + HEIGHT / 2))
  xdotool windowfocus --sync "$main"
  xdotool key ctrl+f; sleep "$attempt"
  xdotool type --delay 40 "$filter"; sleep "$attempt"
  xdotool key Down; sleep 0.3; xdotool key Return
  for i in $(seq 20); do
    dialog=$(xdotool search --onlyvisible --name "^$pattern\$" 2>/dev/null | head -n 1) || true
    if [ -n "$dialog" ]; then
      sleep 1
      eval "$(xdotool getwindowgeometry --shell "$dialog")"   # X Y WIDTH HEIGHT
      # The whole dialog on the screen (MeshLab's has no scroll bar: a row past the bottom edge
      # cannot be reached, nor can the buttons below it).
      read -r screen_width screen_height < <(xdotool getdisplaygeometry)
      if [ $((Y + HEIGHT)) -gt "$screen_height" ]; then
        echo "gui-open-filter: the dialog of '$filter' is $HEIGHT pixels high, taller than the screen's $screen_height" >&2
        exit 1
      fi
      # Close and Apply are the last row of buttons, left and right half, 20 pixels above the bottom.
      echo "$((X + WIDTH * 3 / 4)) $((Y + HEIGHT - 20)) $((X + WIDTH / 4)) $((Y + HEIGHT - 20))"
      exit 0
    fi
    sleep 0.5
  done
  xdotool key Escape; sleep 0.5; xdotool key Escape; sleep 0.5
done
echo "gui-open-filter: the dialog of '$filter' did not open" >&2
exit 1
