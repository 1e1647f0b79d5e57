// The timeline: frame slider, frame field, range, play and stop. Playing shows every frame in turn, advancing when the previous frame's cook arrived.

import type { AppStore } from './store';

export class Timeline {
  playing = false;
  /** One entry per frame shown while playing: how many nodes cooked and came from the cache. */
  readonly playLog: { frame: number; hits: number; misses: number }[] = [];
  private slider: HTMLInputElement;
  private field: HTMLInputElement;
  private start: HTMLInputElement;
  private end: HTMLInputElement;
  private play: HTMLButtonElement;

  constructor(
    host: HTMLElement,
    private store: AppStore,
    private setFrame: (f: number) => void,
  ) {
    host.innerHTML = `<button class="play" title="Play / stop (loops the range)">▶</button>
      <input class="start" type="number" title="First frame"> <input class="slider" type="range" step="1">
      <input class="end" type="number" title="Last frame"> <label>Frame <input class="frame" type="number" step="1"></label>`;
    this.play = host.querySelector('.play')!;
    this.slider = host.querySelector('.slider')!;
    this.field = host.querySelector('.frame')!;
    this.start = host.querySelector('.start')!;
    this.end = host.querySelector('.end')!;
    this.slider.addEventListener('input', () => this.setFrame(Number(this.slider.value)));
    this.field.addEventListener('change', () => this.setFrame(Number(this.field.value)));
    const range = () => {
      const a = Math.round(Number(this.start.value));
      const b = Math.round(Number(this.end.value));
      if (Number.isFinite(a) && Number.isFinite(b) && b >= a) {
        store.range = [a, b];
        store.rangeSet = true;
      }
      this.render();
    };
    this.start.addEventListener('change', range);
    this.end.addEventListener('change', range);
    this.play.addEventListener('click', () => this.toggle());
  }

  toggle() {
    this.playing = !this.playing;
    this.play.textContent = this.playing ? '■' : '▶';
    if (this.playing) this.step();
  }

  /** Called when a cook for the shown frame arrived: log it and go to the next frame. */
  cooked(frame: number, hits: number, misses: number) {
    if (!this.playing) return;
    this.playLog.push({ frame, hits, misses });
    this.step();
  }

  private step() {
    const [a, b] = this.store.range;
    const f = this.store.state?.view.frame ?? a;
    this.setFrame(f >= b || f < a ? a : f + 1);
  }

  render() {
    const [a, b] = this.store.range;
    const f = this.store.state?.view.frame ?? 1;
    this.slider.min = String(a);
    this.slider.max = String(b);
    if (document.activeElement !== this.slider) this.slider.value = String(f);
    if (document.activeElement !== this.field) this.field.value = String(f);
    if (document.activeElement !== this.start) this.start.value = String(a);
    if (document.activeElement !== this.end) this.end.value = String(b);
  }
}
